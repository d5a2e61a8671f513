/* An Embree device whose errors become plumage's. Embree reports errors
 * through a callback (set right after rtcNewDevice) rather than through the
 * results of its calls; plm_embree keeps the first one reported, from any
 * thread, until plm_embree_check turns it into a plm_result. Every build step
 * (rtcCommitScene and the calls before it) is followed by a check. */
#ifndef PLUMAGE_RENDER_EMBREE_H
#define PLUMAGE_RENDER_EMBREE_H

#include <embree3/rtcore.h>
#include <stdatomic.h>
#include <stddef.h>

#include "common/error.h"

typedef struct plm_embree {
    RTCDevice device;
    atomic_int error;      /* the first RTCError since the last check; RTC_ERROR_NONE if none */
    char message[256];     /* Embree's words for it */
    long long memory_limit; /* bytes Embree may hold; 0 = no limit */
    atomic_llong memory;   /* bytes it holds now (counted only with a limit) */
} plm_embree;

/* Creates the device. With memory_limit > 0, an allocation that would take
 * Embree past it fails, as a real allocation failure would (an out-of-memory
 * error at the next check). */
plm_result plm_embree_open(plm_embree *e, long long memory_limit, plm_error *err);

/* PLM_OK if Embree reported nothing since the last check; else the error
 * (PLM_ERR_NO_MEMORY or PLM_ERR_INTERNAL) "Embree, <what>: <its message>", and
 * the record is cleared. */
plm_result plm_embree_check(plm_embree *e, const char *what, plm_error *err);

void plm_embree_close(plm_embree *e);

#endif
