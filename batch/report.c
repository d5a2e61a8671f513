/* What a batch's output folder says: the status table, report.json and a
 * sweep's labelled contact sheet. Everything here reads the job folders
 * alone, so it works the same after a local run or a Slurm array. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "batch/batch.h"
#include "common/progress.h"
#include "common/image_io.h"

#define SHEET_TILE_MAX 256 /* widest image tile on the sheet, pixels */
#define SHEET_TILE_MIN 128 /* smaller images are enlarged (pixel replication) to at least this */
#define SHEET_FONT 13
#define SHEET_LINE 17
#define SHEET_GAP 6
#define SHEET_CHAR_W 8 /* an upper bound of the font's mean advance at SHEET_FONT, to fit the labels */

static int count_lines(const char *s)
{
    int n = 1;
    for (; *s; ++s)
        n += *s == '\n';
    return n;
}

static int longest_line(const char *s)
{
    int most = 0, n = 0;
    for (; *s; ++s) {
        n = *s == '\n' ? 0 : n + 1;
        most = n > most ? n : most;
    }
    return most;
}

/* A sheet cell: the label strip, then the image scaled by a whole factor
 * (shrunk, or enlarged for tiny previews) to fit the tile. */
typedef struct sheet_layout {
    int cols, rows, shrink, zoom, tile_w, tile_h, label_h, cell_w, cell_h, width, height;
} sheet_layout;

static void layout_sheet(const plm_batch *b, int image_w, int image_h, sheet_layout *L)
{
    int last = b->m.key_counts[b->m.n_keys - 1];
    L->cols = b->m.n_keys == 1 && last > 8 ? 8 : last;
    L->rows = (b->m.n_jobs + L->cols - 1) / L->cols;
    L->shrink = (image_w + SHEET_TILE_MAX - 1) / SHEET_TILE_MAX;
    L->zoom = (SHEET_TILE_MIN + image_w - 1) / image_w;
    L->tile_w = image_w * L->zoom / L->shrink;
    L->tile_h = image_h * L->zoom / L->shrink;
    int lines = 1, label_w = 0;
    for (int j = 0; j < b->m.n_jobs; ++j) {
        if (count_lines(b->m.jobs[j].label) > lines)
            lines = count_lines(b->m.jobs[j].label);
        if (longest_line(b->m.jobs[j].label) * SHEET_CHAR_W > label_w)
            label_w = longest_line(b->m.jobs[j].label) * SHEET_CHAR_W;
    }
    L->label_h = lines * SHEET_LINE + SHEET_GAP;
    L->cell_w = (L->tile_w > label_w ? L->tile_w : label_w) + SHEET_GAP;
    L->cell_h = L->label_h + L->tile_h + SHEET_GAP;
    L->width = L->cols * L->cell_w + SHEET_GAP;
    L->height = L->rows * L->cell_h + SHEET_GAP;
}

/* Puts an image into the sheet at (x0, y0): each tile pixel is the mean of
 * a shrink x shrink block, or one pixel repeated zoom x zoom times. */
static void paste(plm_image *sheet, const float *px, int w, int channels, const sheet_layout *L, int x0, int y0)
{
    int s = L->shrink;
    for (int y = 0; y < L->tile_h; ++y)
        for (int x = 0; x < L->tile_w; ++x)
            for (int c = 0; c < 3; ++c) {
                double sum = 0.0;
                for (int dy = 0; dy < s; ++dy)
                    for (int dx = 0; dx < s; ++dx) {
                        size_t sy = (size_t)(y / L->zoom * s + dy), sx = (size_t)(x / L->zoom * s + dx);
                        sum += px[(sy * (size_t)w + sx) * (size_t)channels + (channels >= 3 ? c : 0)];
                    }
                sheet->pixels[((size_t)(y0 + y) * sheet->width + x0 + x) * 3 + c] = (float)(sum / (s * s));
            }
}

static void fill(plm_image *sheet, int x0, int y0, int w, int h, float v)
{
    for (int y = y0; y < y0 + h && y < sheet->height; ++y)
        for (int x = x0; x < x0 + w && x < sheet->width; ++x)
            for (int c = 0; c < 3; ++c)
                sheet->pixels[((size_t)y * sheet->width + x) * 3 + c] = v;
}

static int draw_lines(plm_image *sheet, int x, int y, const char *text, const float color[3])
{
    char buf[1024];
    snprintf(buf, sizeof buf, "%s", text);
    char *save = NULL;
    plm_error err;
    for (char *line = strtok_r(buf, "\n", &save); line; line = strtok_r(NULL, "\n", &save), y += SHEET_LINE)
        if (plm_image_draw_text(sheet, x, y, SHEET_FONT, line, color, &err) != PLM_OK) {
            fprintf(stderr, "error: contact sheet: %s\n", err.message);
            return 0;
        }
    return 1;
}

/* Reads job j's PNG (display values, as written); NULL if it cannot. */
static float *read_job_image(const plm_batch *b, int j, int *w, int *h, int *channels)
{
    char path[PLM_PATH_MAX];
    float *px = NULL;
    if (!plm_batch_job_path(b, j, "image.png", path, sizeof path) ||
        plm_image_read(path, w, h, channels, &px, NULL) != PLM_OK)
        return NULL;
    return px;
}

/* The sweep's images in a grid, each under its parameter values; jobs not
 * done show their state instead. Rows follow the leading keys, columns the
 * last one. Returns 1 on success. */
static int write_contact_sheet(const plm_batch *b, const plm_job_status *st, const char *path)
{
    int w = 0, h = 0, channels = 0, first = -1;
    for (int j = 0; j < b->m.n_jobs && first < 0; ++j)
        if (st[j].state == PLM_JOB_DONE) {
            float *px = read_job_image(b, j, &w, &h, &channels);
            free(px);
            first = px ? j : -1;
        }
    if (first < 0)
        return 1; /* nothing rendered yet: no sheet */
    sheet_layout L;
    layout_sheet(b, w, h, &L);
    plm_image sheet = {L.width, L.height, 3, calloc((size_t)L.width * L.height * 3, sizeof(float))};
    if (!sheet.pixels) {
        fprintf(stderr, "error: contact sheet: out of memory\n");
        return 0;
    }
    fill(&sheet, 0, 0, L.width, L.height, 0.1f);
    static const float white[3] = {0.95f, 0.95f, 0.95f}, red[3] = {1.0f, 0.45f, 0.4f};
    int ok = 1;
    for (int j = 0; j < b->m.n_jobs && ok; ++j) {
        int x0 = SHEET_GAP + (j % L.cols) * L.cell_w, y0 = SHEET_GAP + (j / L.cols) * L.cell_h;
        ok = draw_lines(&sheet, x0 + 2, y0 + SHEET_LINE - 4, b->m.jobs[j].label, white);
        int iw = 0, ih = 0, ic = 0;
        float *px = st[j].state == PLM_JOB_DONE ? read_job_image(b, j, &iw, &ih, &ic) : NULL;
        if (px && iw == w && ih == h) {
            paste(&sheet, px, w, ic, &L, x0, y0 + L.label_h);
        } else {
            fill(&sheet, x0, y0 + L.label_h, L.tile_w, L.tile_h, 0.2f);
            const char *what = px ? "other size" : plm_job_state_names[st[j].state];
            ok = ok && draw_lines(&sheet, x0 + 6, y0 + L.label_h + SHEET_LINE, what, red);
        }
        free(px);
    }
    unsigned char *bytes = ok ? malloc((size_t)L.width * L.height * 3) : NULL;
    for (size_t i = 0; bytes && i < (size_t)L.width * L.height * 3; ++i) {
        float v = sheet.pixels[i] < 0.0f ? 0.0f : (sheet.pixels[i] > 1.0f ? 1.0f : sheet.pixels[i]);
        bytes[i] = (unsigned char)(v * 255.0f + 0.5f);
    }
    plm_error err;
    if (bytes && plm_image_write(path, L.width, L.height, 3, PLM_PIXEL_UINT8, bytes, &err) != PLM_OK) {
        fprintf(stderr, "error: %s\n", err.message);
        ok = 0;
    }
    ok = ok && bytes;
    free(bytes);
    free(sheet.pixels);
    return ok;
}

static plm_job_status *read_states(const plm_batch *b, int counts[PLM_JOB_STATES])
{
    plm_job_status *st = calloc((size_t)b->m.n_jobs, sizeof *st);
    memset(counts, 0, PLM_JOB_STATES * sizeof *counts);
    for (int j = 0; st && j < b->m.n_jobs; ++j) {
        plm_batch_job_status(b, j, &st[j]);
        ++counts[st[j].state];
    }
    if (!st)
        fprintf(stderr, "error: out of memory\n");
    return st;
}

static void print_counts(FILE *out, const plm_batch *b, const int counts[PLM_JOB_STATES])
{
    fprintf(out, "%d jobs: %d done, %d failed, %d killed, %d missing", b->m.n_jobs, counts[PLM_JOB_DONE],
            counts[PLM_JOB_FAILED], counts[PLM_JOB_KILLED], counts[PLM_JOB_MISSING]);
    if (counts[PLM_JOB_RUNNING])
        fprintf(out, ", %d running", counts[PLM_JOB_RUNNING]);
    fputc('\n', out);
}

int plm_batch_gather(const plm_batch *b, int explain, int quiet)
{
    int counts[PLM_JOB_STATES];
    plm_job_status *st = read_states(b, counts);
    if (!st)
        return b->m.n_jobs;
    char path[PLM_PATH_MAX];
    cJSON *doc = cJSON_CreateObject();
    cJSON_AddStringToObject(doc, "manifest", b->manifest_path);
    cJSON_AddNumberToObject(doc, "jobs", b->m.n_jobs);
    for (int s = 0; s < PLM_JOB_STATES; ++s)
        cJSON_AddNumberToObject(doc, plm_job_state_names[s], counts[s]);
    int sheet_ok = 1;
    if (b->m.n_keys > 0) {
        snprintf(path, sizeof path, "%s/contact_sheet.png", b->out);
        sheet_ok = write_contact_sheet(b, st, path);
        cJSON_AddStringToObject(doc, "contact_sheet", "contact_sheet.png");
    }
    cJSON *list = cJSON_AddArrayToObject(doc, "list");
    for (int j = 0; j < b->m.n_jobs; ++j) {
        cJSON *e = cJSON_CreateObject();
        cJSON_AddNumberToObject(e, "job", j);
        cJSON_AddStringToObject(e, "name", b->m.jobs[j].name);
        cJSON_AddStringToObject(e, "label", b->m.jobs[j].label);
        cJSON_AddStringToObject(e, "state", plm_job_state_names[st[j].state]);
        cJSON_AddStringToObject(e, "runner", st[j].runner);
        if (st[j].state == PLM_JOB_DONE)
            cJSON_AddNumberToObject(e, "seconds", st[j].seconds);
        if (st[j].message[0])
            cJSON_AddStringToObject(e, "message", st[j].message);
        cJSON_AddItemToArray(list, e);
        if (explain && st[j].state != PLM_JOB_DONE)
            fprintf(stderr, "job %s %s%s%s (see %s/%s/)\n", b->m.jobs[j].name, plm_job_state_names[st[j].state],
                    st[j].message[0] ? ": " : "", st[j].message, b->out, b->m.jobs[j].name);
    }
    snprintf(path, sizeof path, "%s/report.json", b->out);
    int report_ok = plm_batch_write_json(path, doc);
    cJSON_Delete(doc);
    if (!explain && counts[PLM_JOB_DONE] < b->m.n_jobs) {
        fprintf(stderr, "not done:");
        for (int j = 0; j < b->m.n_jobs; ++j)
            if (st[j].state != PLM_JOB_DONE)
                fprintf(stderr, " %s (%s)", b->m.jobs[j].name, plm_job_state_names[st[j].state]);
        fprintf(stderr, "\n");
    }
    if (!quiet || counts[PLM_JOB_DONE] < b->m.n_jobs)
        print_counts(stderr, b, counts);
    if (report_ok) {
        char sheet[PLM_PATH_MAX + 32] = "";
        if (b->m.n_keys > 0 && sheet_ok && counts[PLM_JOB_DONE] > 0)
            snprintf(sheet, sizeof sheet, "%s/contact_sheet.png", b->out);
        plm_print_wrote((const char *const[]){path, sheet}, 2);
    }
    free(st);
    int not_done = b->m.n_jobs - counts[PLM_JOB_DONE];
    return not_done ? not_done : !(sheet_ok && report_ok);
}

int plm_batch_print_status(const plm_batch *b)
{
    int counts[PLM_JOB_STATES];
    plm_job_status *st = read_states(b, counts);
    if (!st)
        return b->m.n_jobs;
    printf("%-24s %-8s %-20s %9s  %s\n", "job", "state", "ran", "seconds", "parameters / message");
    for (int j = 0; j < b->m.n_jobs; ++j) {
        char label[256];
        snprintf(label, sizeof label, "%s", st[j].message[0] ? st[j].message : b->m.jobs[j].label);
        for (char *p = label; *p; ++p)
            *p = *p == '\n' ? ' ' : *p;
        char secs[32] = "";
        if (st[j].state == PLM_JOB_DONE)
            snprintf(secs, sizeof secs, "%.2f", st[j].seconds);
        printf("%-24s %-8s %-20s %9s  %s\n", b->m.jobs[j].name, plm_job_state_names[st[j].state],
               st[j].runner[0] ? st[j].runner : "-", secs, label);
    }
    print_counts(stdout, b, counts);
    free(st);
    return b->m.n_jobs - counts[PLM_JOB_DONE];
}
