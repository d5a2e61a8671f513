#include "common/memory.h"

#include <stdio.h>
#include <string.h>

/* The value of a "Name:   1234 kB" line of /proc/self/status, in MiB. */
static double status_mib(const char *name)
{
    FILE *f = fopen("/proc/self/status", "r");
    if (!f)
        return 0.0;
    char line[256];
    size_t len = strlen(name);
    double kib = 0.0;
    while (fgets(line, sizeof line, f))
        if (strncmp(line, name, len) == 0 && line[len] == ':' && sscanf(line + len + 1, "%lf", &kib) == 1)
            break;
    fclose(f);
    return kib / 1024.0;
}

double plm_memory_resident_mib(void)
{
    return status_mib("VmRSS");
}

double plm_memory_peak_mib(void)
{
    return status_mib("VmHWM");
}

int plm_memory_reset_peak(void)
{
    /* Linux: writing 5 to clear_refs resets the peak resident set size. */
    FILE *f = fopen("/proc/self/clear_refs", "w");
    if (!f)
        return 0;
    int ok = fputs("5", f) >= 0;
    ok = (fclose(f) == 0) && ok;
    return ok;
}
