"""Data files the generator reads: the vendor SVD of the STM32F103 (see NOTICE.md)."""
