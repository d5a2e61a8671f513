/* `plumage generate --contact-sheet`: every species named, rendered front
 * and back under a side light, in a labelled grid (docs/generating.md). */
#ifndef PLUMAGE_CLI_SPECIES_SHEET_H
#define PLUMAGE_CLI_SPECIES_SHEET_H

typedef struct plm_species_sheet_options {
    int spp;          /* samples per pixel of each view */
    int tile;         /* a view's height in pixels; its width is half that */
    int columns;      /* species per row; 0 = up to 6 */
    int threads;      /* render threads; 0 = all cores */
    int level;        /* subdivision level of the meshes */
    int texture_size; /* feather texture size */
    int quiet;        /* no progress lines */
} plm_species_sheet_options;

/* Renders the species files into the PNG `out`. Every file is read and the
 * output checked before the first render. Returns the exit status. */
int plm_species_sheet(const char *out, const char *const *files, int n, const plm_species_sheet_options *opt);

#endif
