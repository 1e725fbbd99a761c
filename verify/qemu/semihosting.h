/*
 * ARM semihosting for the Unity runs under qemu-system-arm (-semihosting-config
 * enable=on,target=native): characters to the host's standard output and the test
 * program's exit status back to the host, through `bkpt 0xab` on the Cortex-M3.
 * Not for a real board without a debugger attached: there the BKPT is a HardFault.
 */
#ifndef SEMIHOSTING_H
#define SEMIHOSTING_H

#include <stdint.h>

/* Unity's output hook (UNITY_OUTPUT_CHAR=semihosting_putchar): buffers one line and
 * writes it with SYS_WRITE0, one trap per line instead of one per character. */
void semihosting_putchar(int c);

/* Writes out what is buffered. */
void semihosting_flush(void);

/* Ends the emulation with this exit status (SYS_EXIT_EXTENDED, else SYS_EXIT). */
void semihosting_exit(uint32_t status) __attribute__((noreturn));

#endif /* SEMIHOSTING_H */
