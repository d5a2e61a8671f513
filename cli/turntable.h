/* plumage render --turntable N: the camera orbits the subject, N frames
 * evenly spaced over one full turn about the camera's up axis through the
 * point it looks at. The world (Embree scenes, fiber tables) is built once
 * for all frames. Frames are numbered after the outputs' names
 * (frame.png -> frame_000.png, frame_001.png, ...), and where ffmpeg is on
 * the PATH the PNGs become an MP4 beside them (frame.mp4), written atomically
 * like every output. */
#ifndef PLUMAGE_CLI_TURNTABLE_H
#define PLUMAGE_CLI_TURNTABLE_H

#include "render/render.h"

#define PLM_TURNTABLE_MAX 100000

typedef struct plm_turntable {
    int frames;
    const char *png, *exr; /* the names frames are numbered after; "" = not written */
    double fps;            /* of the MP4 [24] */
} plm_turntable;

/* Numbered name of frame k of `frames` after `path` ("dir/f.png" -> "dir/f_007.png"):
 * at least three digits, more when the sequence needs them. */
void plm_turntable_frame_path(const char *path, int k, int frames, char *out, size_t size);

/* Renders and writes every frame; *total gets the sequence's totals (samples,
 * rays, seconds, non-finite samples, whether Ctrl-C stopped it; no pixels).
 * Progress: the render's own bar per frame and a line per frame with the time
 * left for the whole sequence. Prints the MP4's fate; the caller prints "wrote". */
plm_result plm_turntable_render(const plm_scene *scene, const plm_render_options *ro, const plm_picture *picture,
                                const plm_turntable *t, plm_film *total, char *mp4, size_t mp4_size,
                                plm_error *err);

#endif
