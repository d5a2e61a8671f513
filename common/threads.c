#include "common/threads.h"

#include <stdlib.h>

#include "common/clock.h"

int plm_threads_start(plm_threads *t, int n, void *(*fn)(void *), void *arg)
{
    n = n > 0 ? n : plm_cores();
    t->started = 0;
    t->ids = calloc((size_t)n, sizeof *t->ids);
    while (t->ids && t->started < n && pthread_create(&t->ids[t->started], NULL, fn, arg) == 0)
        ++t->started;
    return t->started;
}

void plm_threads_join(plm_threads *t)
{
    for (int i = 0; i < t->started; ++i)
        pthread_join(t->ids[i], NULL);
    free(t->ids);
    t->ids = NULL;
    t->started = 0;
}
