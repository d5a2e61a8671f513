/* Progress on stderr in one style for every long task (a render, a batch, a
 * figure, a fiber table):
 *
 *   render [############..................]  40%  2.9e+05 samples/s  12 s left
 *
 * On a terminal the line is redrawn in place. Anywhere else (a log file, a
 * pipe) plain lines are printed instead, at most one per tenth of the work
 * and none in a task's first 2 seconds, and never a carriage return, so logs
 * stay readable. Every task ends with its finishing line. */
#ifndef PLUMAGE_COMMON_PROGRESS_H
#define PLUMAGE_COMMON_PROGRESS_H

typedef struct plm_progress {
    char what[64];
    int tty;           /* stderr is a terminal: redraw in place */
    double start;      /* seconds, monotonic */
    int tenths;        /* plain lines: tenths of the work printed so far */
    int drawn;         /* a line drawn in place is waiting for its end */
} plm_progress;

/* Starts the clock; `what` names the task at the start of every line. */
void plm_progress_start(plm_progress *p, const char *what);

/* The work done, as a fraction in [0, 1], and an optional detail (NULL or
 * "": none) such as a rate. The time left is estimated from the time so far. */
void plm_progress_update(plm_progress *p, double fraction, const char *detail);

/* The last line: the bar at `fraction` with the detail and the time taken. */
void plm_progress_finish(plm_progress *p, double fraction, const char *detail);

/* The last line of a command that wrote files, on stderr: "wrote A B ..."
 * (NULL and "" entries are skipped; docs/README.md, "Outputs"). */
void plm_print_wrote(const char *const *paths, int n);

#endif
