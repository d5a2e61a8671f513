#include "cli/figure.h"

#include <stdio.h>
#include <stdlib.h>

const float plm_figure_ink[3] = {0.0f, 0.0f, 0.0f};

int plm_figure_text_width(const char *text, int size)
{
    int glyphs = 0;
    for (const char *c = text; *c; ++c)
        glyphs += ((unsigned char)*c & 0xc0) != 0x80; /* UTF-8 lead bytes */
    return (int)(0.6 * size * glyphs);
}

void plm_figure_fill(plm_image *img, int x0, int y0, int w, int h, const float c[3])
{
    for (int y = y0; y < y0 + h; ++y)
        for (int x = x0; x < x0 + w; ++x)
            for (int k = 0; k < 3; ++k)
                img->pixels[3 * ((size_t)y * (size_t)img->width + (size_t)x) + k] = c[k];
}

plm_image plm_figure_page(int w, int h)
{
    plm_image img = {w, h, 3, malloc((size_t)w * (size_t)h * 3 * sizeof(float))};
    static const float white[3] = {1.0f, 1.0f, 1.0f};
    if (img.pixels)
        plm_figure_fill(&img, 0, 0, w, h, white);
    else
        fprintf(stderr, "error: out of memory for a %d x %d figure\n", w, h);
    return img;
}

plm_result plm_figure_axes(plm_image *img, int x0, int y0, int w, int h, const char *const *below, int n_below,
                           const char *const *left, int n_left, plm_error *err)
{
    const int size = PLM_FIGURE_FONT_SMALL;
    plm_result rc = PLM_OK;
    for (int i = 0; i < n_below && rc == PLM_OK; ++i) {
        int x = x0 + (w - 1) * i / (n_below - 1);
        plm_figure_fill(img, x, y0 + h, 1, 4, plm_figure_ink);
        rc = plm_image_draw_text(img, x - plm_figure_text_width(below[i], size) / 2, y0 + h + 5 + size, size, below[i],
                                 plm_figure_ink, err);
    }
    for (int i = 0; i < n_left && rc == PLM_OK; ++i) {
        int y = y0 + (h - 1) * i / (n_left - 1);
        plm_figure_fill(img, x0 - 4, y, 4, 1, plm_figure_ink);
        rc = plm_image_draw_text(img, x0 - 7 - plm_figure_text_width(left[i], size), y + size / 3, size, left[i],
                                 plm_figure_ink, err);
    }
    return rc;
}

plm_result plm_figure_legend(plm_image *img, int x, int y, const float (*colors)[3], const char *const *names, int n,
                             plm_error *err)
{
    plm_result rc = PLM_OK;
    for (int i = 0; i < n && rc == PLM_OK; ++i) {
        plm_figure_fill(img, x, y, 14, 14, colors[i]);
        rc = plm_image_draw_text(img, x + 20, y + 12, PLM_FIGURE_FONT, names[i], plm_figure_ink, err);
        x += 20 + plm_figure_text_width(names[i], PLM_FIGURE_FONT) + 22;
    }
    return rc;
}
