"""Processor-in-the-loop: the linked STM32F103 firmware ELF, byte for byte, on an
emulated chip (unicorn's Cortex-M3 plus peripheral models written from RM0008)."""
