/* The clocks and the core count every part of plumage times and sizes its
 * work with, in one place: wall seconds for progress and figures, CPU
 * seconds where other processes share the cores (benchmarks), and the cores
 * a default thread count takes. */
#ifndef PLUMAGE_COMMON_CLOCK_H
#define PLUMAGE_COMMON_CLOCK_H

/* Seconds on a monotonic wall clock, from an arbitrary start. */
double plm_seconds(void);
/* CPU seconds this process has used (all its threads): unlike the wall
 * clock, not inflated when other processes share the cores. */
double plm_cpu_seconds(void);
/* CPU seconds the calling thread has used. */
double plm_thread_seconds(void);
/* The cores online, at least 1: the default number of threads. */
int plm_cores(void);

#endif
