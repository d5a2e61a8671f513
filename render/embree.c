#include "render/embree.h"

#include <stdio.h>
#include <string.h>

static void on_error(void *user, enum RTCError code, const char *text)
{
    plm_embree *e = user;
    int none = RTC_ERROR_NONE;
    /* The first error wins; later ones are usually its consequences. */
    if (atomic_compare_exchange_strong(&e->error, &none, (int)code))
        snprintf(e->message, sizeof e->message, "%s", text ? text : "no description");
}

/* Called before each allocation (post = false; refusing it makes Embree fail
 * the operation with an out-of-memory error) and after some (post = true:
 * already made, so it stays counted) with the size; frees come negative. */
static bool on_memory(void *user, ssize_t bytes, bool post)
{
    plm_embree *e = user;
    long long now = atomic_fetch_add(&e->memory, (long long)bytes) + (long long)bytes;
    if (bytes > 0 && now > e->memory_limit) {
        if (!post)
            atomic_fetch_sub(&e->memory, (long long)bytes);
        return false;
    }
    return true;
}

plm_result plm_embree_open(plm_embree *e, long long memory_limit, plm_error *err)
{
    memset(e, 0, sizeof *e);
    atomic_init(&e->error, RTC_ERROR_NONE);
    atomic_init(&e->memory, 0);
    e->memory_limit = memory_limit;
    e->device = rtcNewDevice(NULL);
    if (!e->device)
        return plm_fail(err, PLM_ERR_INTERNAL, "Embree: cannot create a device (error %d)",
                        (int)rtcGetDeviceError(NULL));
    rtcSetDeviceErrorFunction(e->device, on_error, e);
    if (memory_limit > 0)
        rtcSetDeviceMemoryMonitorFunction(e->device, on_memory, e);
    return PLM_OK;
}

plm_result plm_embree_check(plm_embree *e, const char *what, plm_error *err)
{
    int code = atomic_load(&e->error);
    if (code == RTC_ERROR_NONE)
        return PLM_OK;
    plm_result rc = code == RTC_ERROR_OUT_OF_MEMORY ? PLM_ERR_NO_MEMORY : PLM_ERR_INTERNAL;
    plm_fail(err, rc, "Embree, %s: %s%s", what, code == RTC_ERROR_OUT_OF_MEMORY ? "out of memory: " : "", e->message);
    atomic_store(&e->error, RTC_ERROR_NONE);
    return rc;
}

void plm_embree_close(plm_embree *e)
{
    if (e->device)
        rtcReleaseDevice(e->device);
    e->device = NULL;
}
