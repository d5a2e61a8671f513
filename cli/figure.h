/* What the probes' labelled pictures share (Fig. 7, Fig. 9): filled blocks,
 * text and axis ticks drawn into a float RGB image on a white page. */
#ifndef PLUMAGE_CLI_FIGURE_H
#define PLUMAGE_CLI_FIGURE_H

#include "common/image_io.h"

enum { PLM_FIGURE_FONT = 13, PLM_FIGURE_FONT_SMALL = 11 };

extern const float plm_figure_ink[3];

/* About the width of text in DejaVu Sans at `size` px, to centre or fit labels. */
int plm_figure_text_width(const char *text, int size);

void plm_figure_fill(plm_image *img, int x0, int y0, int w, int h, const float c[3]);

/* A white page of w x h pixels (pixels NULL, message on stderr, if out of memory). */
plm_image plm_figure_page(int w, int h);

/* Ticks under the panel at (x0, y0), w x h, with labels spread evenly from
 * its left to its right edge; with left labels, ticks on its left from its
 * top to its bottom edge too. */
plm_result plm_figure_axes(plm_image *img, int x0, int y0, int w, int h, const char *const *below, int n_below,
                           const char *const *left, int n_left, plm_error *err);

/* Coloured squares, each followed by its name, in a row from (x, y) (y: the squares' top). */
plm_result plm_figure_legend(plm_image *img, int x, int y, const float (*colors)[3], const char *const *names, int n,
                             plm_error *err);

#endif
