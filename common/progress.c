#define _POSIX_C_SOURCE 200809L /* isatty */
#include "common/progress.h"
#include "common/clock.h"

#include <math.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

enum { BAR = 30 };

void plm_progress_start(plm_progress *p, const char *what)
{
    snprintf(p->what, sizeof p->what, "%s", what);
    p->tty = isatty(2);
    p->start = plm_seconds();
    p->tenths = 0;
    p->drawn = 0;
}

/* "12 s" or "3:05" (minutes). */
static void format_time(double s, char *out, size_t size)
{
    long t = lround(s);
    if (t < 100)
        snprintf(out, size, "%ld s", t);
    else
        snprintf(out, size, "%ld:%02ld", t / 60, t % 60);
}

static void print_line(plm_progress *p, double fraction, const char *detail, int last)
{
    fraction = fraction < 0.0 ? 0.0 : (fraction > 1.0 ? 1.0 : fraction);
    char bar[BAR + 1], span[24] = "", time[40] = "";
    int filled = (int)(fraction * BAR);
    for (int i = 0; i < BAR; ++i)
        bar[i] = i < filled ? '#' : '.';
    bar[BAR] = '\0';
    double elapsed = plm_seconds() - p->start;
    if (last) {
        format_time(elapsed, span, sizeof span);
        snprintf(time, sizeof time, "in %s", span);
    } else if (fraction > 0.0) {
        format_time(elapsed * (1.0 - fraction) / fraction, span, sizeof span);
        snprintf(time, sizeof time, "%s left", span);
    }
    fprintf(stderr, "%s%s [%s] %3.0f%%%s%s%s%s%s", p->tty ? "\r" : "", p->what, bar, 100.0 * fraction,
            detail && detail[0] ? "  " : "", detail ? detail : "", time[0] ? "  " : "", time,
            p->tty && !last ? "   " : "\n");
    fflush(stderr);
    p->drawn = p->tty && !last;
}

void plm_progress_update(plm_progress *p, double fraction, const char *detail)
{
    if (!p->tty) { /* a line per tenth, once the task has run long enough to be waited for */
        int tenths = (int)floor(10.0 * fraction);
        if (tenths <= p->tenths || tenths >= 10 || plm_seconds() - p->start < 2.0)
            return;
        p->tenths = tenths;
    }
    print_line(p, fraction, detail, 0);
}

void plm_progress_finish(plm_progress *p, double fraction, const char *detail)
{
    print_line(p, fraction, detail, 1);
}

void plm_print_wrote(const char *const *paths, int n)
{
    fputs("wrote", stderr);
    for (int i = 0; i < n; ++i)
        if (paths[i] && paths[i][0])
            fprintf(stderr, " %s", paths[i]);
    fputc('\n', stderr);
}
