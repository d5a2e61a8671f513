/* Timing helpers for `plumage bench`. Benchmarks print figures; they are
 * never tests, and nothing asserts on a time. */
#ifndef PLUMAGE_CLI_BENCH_H
#define PLUMAGE_CLI_BENCH_H

/* Runs body(ctx, calls) `runs` times and returns the median nanoseconds per
 * call (single thread, wall clock, after one warm-up run). */
double plm_bench_ns_per_call(void (*body)(void *ctx, long calls), void *ctx, long calls, int runs);

/* Seconds since an arbitrary start (monotonic). */
double plm_bench_seconds(void);

#endif
