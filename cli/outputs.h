/* One rule for every command that writes files (docs/README.md, "Outputs"):
 * before any work, the folder each output goes into is created if missing
 * (with its parents) and must take a new file, and a file must not name a
 * folder. A command that then fails removes the folders it created, if they
 * are still empty, so it leaves nothing behind. A command that wrote files
 * ends with one line on stderr: "wrote PATH..." (stdout carries only data). */
#ifndef PLUMAGE_CLI_OUTPUTS_H
#define PLUMAGE_CLI_OUTPUTS_H

#include "common/progress.h" /* plm_print_wrote */

#define PLM_OUTPUTS_MAX 4
#define PLM_OUTPUTS_PATH 4096

typedef struct plm_outputs {
    int count;
    struct {
        char folder[PLM_OUTPUTS_PATH]; /* the folder checked */
        char made[PLM_OUTPUTS_PATH];   /* the outermost folder the check created, or "" */
    } at[PLM_OUTPUTS_MAX];
} plm_outputs;

/* Checks (and prepares) the folder the file `path` goes into. `option`
 * names where the path came from in the message ("-o", "film.png"). Returns
 * 1, or 0 after "error: OPTION PATH: ..." on stderr. A device or pipe that
 * exists (/dev/null) is taken as it is. */
int plm_outputs_file(plm_outputs *o, const char *option, const char *path);

/* The same for an output folder itself. */
int plm_outputs_folder(plm_outputs *o, const char *option, const char *folder);

/* A benchmark's --images PREFIX: the folder PREFIX_<case>.png files go into
 * is checked (and made) as plm_outputs_file does; returns 1, or 0 after a message. */
int plm_images_prefix_ok(const char *prefix);

/* The command failed: removes the folders the checks created, innermost
 * first, as far as they are empty. */
void plm_outputs_undo(plm_outputs *o);


#endif
