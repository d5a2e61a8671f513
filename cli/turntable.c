#include "cli/turntable.h"
#include "common/clock.h"

#include <errno.h>
#include <math.h>
#include <spawn.h>
#include <stdio.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "render/transform.h"

extern char **environ;

static int frame_digits(int frames)
{
    int digits = 1;
    for (int n = frames - 1; n >= 10; n /= 10)
        ++digits;
    return digits < 3 ? 3 : digits;
}

/* "dir/f.png" -> stem "dir/f" and extension ".png" (a dot in a folder name is not an extension). */
static void split_extension(const char *path, int *stem_len, const char **ext)
{
    const char *slash = strrchr(path, '/'), *dot = strrchr(path, '.');
    if (!dot || (slash && dot < slash))
        dot = path + strlen(path);
    *stem_len = (int)(dot - path);
    *ext = dot;
}

void plm_turntable_frame_path(const char *path, int k, int frames, char *out, size_t size)
{
    int stem;
    const char *ext;
    split_extension(path, &stem, &ext);
    snprintf(out, size, "%.*s_%0*d%s", stem, path, frame_digits(frames), k, ext);
}

/* The camera of frame k: turned by k/frames of a full turn about its up axis through look_at. */
static plm_camera_desc orbit(plm_camera_desc d, int k, int frames)
{
    plm_xform r = plm_xform_rotate(v3_normalize(d.up), 2.0 * PLM_PI * k / frames);
    d.position = v3_add(d.look_at, plm_xform_vector(r.m, v3_sub(d.position, d.look_at)));
    return d;
}

/* ffmpeg's input pattern for the PNG frames: the numbered name with '%' escaped. */
static void ffmpeg_pattern(const char *png, int frames, char *out, size_t size)
{
    int stem;
    const char *ext;
    split_extension(png, &stem, &ext);
    size_t n = 0;
    for (int i = 0; i < stem && n + 2 < size; ++i) {
        if (png[i] == '%')
            out[n++] = '%';
        out[n++] = png[i];
    }
    snprintf(out + n, size - n, "_%%0%dd%s", frame_digits(frames), ext);
}

/* Runs ffmpeg on the frames into mp4 (through a temporary name). Returns 1 if
 * written, 0 if ffmpeg is missing or failed (said on stderr). */
static int write_mp4(const plm_turntable *t, const char *mp4)
{
    char pattern[4200], tmp[4200], fps[32];
    ffmpeg_pattern(t->png, t->frames, pattern, sizeof pattern);
    snprintf(tmp, sizeof tmp, "%s.part", mp4);
    snprintf(fps, sizeof fps, "%g", t->fps > 0 ? t->fps : 24.0);
    /* yuv420p (what every player takes) needs even sides: pad by a pixel where odd. */
    char *argv[] = {"ffmpeg", "-nostdin", "-loglevel", "error", "-y", "-framerate", fps, "-i", pattern,
                    "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-c:v", "libx264", "-pix_fmt", "yuv420p",
                    "-f", "mp4", tmp, NULL};
    pid_t pid;
    int spawned = posix_spawnp(&pid, "ffmpeg", NULL, NULL, argv, environ);
    if (spawned != 0) {
        fprintf(stderr, "no MP4: ffmpeg is not installed (on Debian: apt install ffmpeg); the frames are written\n");
        return 0;
    }
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR)
        ;
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || rename(tmp, mp4) != 0) {
        fprintf(stderr, "no MP4: ffmpeg failed on %s (the frames are written)\n", pattern);
        unlink(tmp);
        return 0;
    }
    return 1;
}

static void add_totals(plm_film *total, const plm_film *frame)
{
    total->width = frame->width;
    total->height = frame->height;
    total->threads = frame->threads;
    total->sample_count += frame->sample_count;
    total->ray_count += frame->ray_count;
    total->nonfinite += frame->nonfinite;
    total->seconds += frame->seconds;
    total->interrupted |= frame->interrupted;
}

static plm_result render_frames(plm_world *world, const plm_render_options *ro, const plm_picture *picture,
                                const plm_turntable *t, plm_film *total, plm_error *err)
{
    const plm_camera_desc start = plm_world_camera_desc(world);
    double t0 = plm_seconds();
    for (int k = 0; k < t->frames && !total->interrupted; ++k) {
        plm_camera_desc d = orbit(start, k, t->frames);
        plm_world_set_camera(world, &d);
        char png[4200] = "", exr[4200] = "";
        if (t->png[0])
            plm_turntable_frame_path(t->png, k, t->frames, png, sizeof png);
        if (t->exr[0])
            plm_turntable_frame_path(t->exr, k, t->frames, exr, sizeof exr);
        plm_film film;
        plm_result rc = plm_render_world(world, ro, &film, err);
        if (rc == PLM_OK)
            rc = plm_film_write(&film, exr, png, picture, err);
        if (rc == PLM_OK)
            add_totals(total, &film);
        plm_film_free(&film);
        if (rc != PLM_OK)
            return rc;
        double elapsed = plm_seconds() - t0, left = elapsed / (k + 1) * (t->frames - k - 1);
        fprintf(stderr, "frame %d of %d: %s%s%s  (%.0f s so far, about %.0f s left)\n", k + 1, t->frames, png,
                png[0] && exr[0] ? " " : "", exr, elapsed, left);
    }
    return PLM_OK;
}

plm_result plm_turntable_render(const plm_scene *scene, const plm_render_options *ro, const plm_picture *picture,
                                const plm_turntable *t, plm_film *total, char *mp4, size_t mp4_size,
                                plm_error *err)
{
    memset(total, 0, sizeof *total);
    mp4[0] = '\0';
    plm_world world;
    plm_result rc = plm_world_build(scene, &world, err);
    if (rc != PLM_OK)
        return rc;
    rc = render_frames(&world, ro, picture, t, total, err);
    if (rc == PLM_OK)
        rc = plm_embree_check(&world.embree, "tracing rays", err);
    plm_world_free(&world);
    if (rc == PLM_OK && !total->interrupted && t->png[0]) {
        int stem;
        const char *ext;
        split_extension(t->png, &stem, &ext);
        snprintf(mp4, mp4_size, "%.*s.mp4", stem, t->png);
        if (!write_mp4(t, mp4))
            mp4[0] = '\0';
    }
    return rc;
}
