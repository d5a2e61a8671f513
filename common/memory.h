/* This process's resident memory, for the figures commands and benchmarks
 * print (Linux: /proc/self/status). A command that reads no image starts
 * small, because the image library is loaded on first use (see
 * docs/benchmarks.md), so the difference between the peak and the resident
 * memory before a piece of work is what that work cost. */
#ifndef PLUMAGE_COMMON_MEMORY_H
#define PLUMAGE_COMMON_MEMORY_H

/* Resident memory now, in MiB (0 if the system does not say). */
double plm_memory_resident_mib(void);

/* Peak resident memory since the process started or since the last
 * plm_memory_reset_peak, in MiB (0 if the system does not say). */
double plm_memory_peak_mib(void);

/* Makes the peak the current resident memory, so that the next peak is one
 * piece of work's alone. Returns 0 where the system cannot do it (the peak
 * then stays the process's). */
int plm_memory_reset_peak(void);

#endif
