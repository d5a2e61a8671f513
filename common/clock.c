#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#include "common/clock.h"

#include <time.h>
#include <unistd.h>

static double seconds_of(clockid_t clock)
{
    struct timespec ts;
    clock_gettime(clock, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

double plm_seconds(void) { return seconds_of(CLOCK_MONOTONIC); }
double plm_cpu_seconds(void) { return seconds_of(CLOCK_PROCESS_CPUTIME_ID); }
double plm_thread_seconds(void) { return seconds_of(CLOCK_THREAD_CPUTIME_ID); }

int plm_cores(void)
{
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n > 0 ? (int)n : 1;
}
