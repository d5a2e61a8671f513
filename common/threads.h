/* The one way plumage runs work on threads (the renderer's tiles, the fiber
 * tables' builds): start as many as asked, or one per core, and carry on
 * with those that did start; with none, the caller does the work itself. */
#ifndef PLUMAGE_COMMON_THREADS_H
#define PLUMAGE_COMMON_THREADS_H

#include <pthread.h>

typedef struct plm_threads {
    pthread_t *ids;
    int started;
} plm_threads;

/* Starts up to n threads (n <= 0: plm_cores(), common/clock.h) running
 * fn(arg). Returns how many started: 0 if none could (then run fn on this
 * thread), and the caller sizes its synchronisation to the number. */
int plm_threads_start(plm_threads *t, int n, void *(*fn)(void *), void *arg);
/* Waits for the threads started, and frees them. */
void plm_threads_join(plm_threads *t);

#endif
