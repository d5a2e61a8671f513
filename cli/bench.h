/* Timing helpers for `plumage bench`. Benchmarks print figures; they are
 * never tests, and nothing asserts on a time. */
#ifndef PLUMAGE_CLI_BENCH_H
#define PLUMAGE_CLI_BENCH_H

#include <stddef.h>

/* Runs body(ctx, calls) `runs` times and returns the median nanoseconds per
 * call (single thread, wall clock, after one warm-up run). */
double plm_bench_ns_per_call(void (*body)(void *ctx, long calls), void *ctx, long calls, int runs);


/* Runs measure(ctx, figures) in a child process, so that the peak memory it
 * reports is its own, and copies the size bytes of *figures it filled back
 * over the pipe. Returns 1 if the child returned 1 and its figures arrived. */
int plm_bench_in_child(int (*measure)(void *ctx, void *figures), void *ctx, void *figures, size_t size);

#endif
