/* The fiber options shared by `plumage probe fiber`, `plumage probe bcsdf`
 * (docs/fiber.md): one table, one conversion to plm_fiber_params. */
#ifndef PLUMAGE_CLI_FIBER_CLI_H
#define PLUMAGE_CLI_FIBER_CLI_H

#include "cli/options.h"
#include "optics/fiber.h"

/* Command-line values (angles in degrees), filled with the defaults by plm_fiber_cli_options. */
#define PLM_FIBER_CLI_OPTIONS 9

typedef struct plm_fiber_cli {
    double eccentricity, eta, sigma_a[3], beta_m_deg, beta_n_deg;
    double medulla_axes[2], medulla_centre[2], medulla_reflectance[3];
    int lobes;
    plm_option_text text[PLM_FIBER_CLI_OPTIONS]; /* the options' names and help, from the fiber table */
} plm_fiber_cli;

/* Sets c to the defaults and writes the PLM_FIBER_CLI_OPTIONS options that
 * fill it into opts; --lobes accepts [1, max_lobes]. */
void plm_fiber_cli_options(plm_fiber_cli *c, plm_option *opts, int max_lobes);

/* Converts to parameters and validates them; on failure prints
 * "error: <command>: <reason>" and returns 0. */
int plm_fiber_cli_params(const plm_fiber_cli *c, const char *command, plm_fiber_params *p);

#endif
