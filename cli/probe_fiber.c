/* plumage probe fiber: the lobes the fiber tracer produces for given view
 * directions and entry offsets (docs/fiber.md), and the fiber options shared with
 * the bcsdf probe. */
#include <stdio.h>
#include <string.h>

#include "cli/commands.h"
#include "cli/fiber_cli.h"

void plm_fiber_cli_options(plm_fiber_cli *c, plm_option *opts, int max_lobes)
{
    plm_fiber_params d;
    plm_fiber_params_default(&d);
    *c = (plm_fiber_cli){.eccentricity = d.eccentricity, .eta = d.eta,
                         .sigma_a = {d.sigma_a.r, d.sigma_a.g, d.sigma_a.b},
                         .beta_m_deg = plm_degrees(d.beta_m), .beta_n_deg = plm_degrees(d.beta_n),
                         .medulla_reflectance = {d.medulla_reflectance.r, d.medulla_reflectance.g,
                                                 d.medulla_reflectance.b},
                         .lobes = d.lobes};
    /* Names, ranges, meanings and units are the fiber table's (optics/fiber_params.h), as in scene files. */
    static const char *const fields[PLM_FIBER_CLI_OPTIONS] = {
        "eccentricity", "eta",           "sigma_a",        "beta_m",         "beta_n", "medulla_axes",
        "medulla_centre", "medulla_reflectance", "lobes"};
    static const char *const metavars[PLM_FIBER_CLI_OPTIONS] = {"E", "ETA", "R,G,B", "DEG", "DEG", "A,B", "CA,CB",
                                                               "R,G,B", "N"};
    void *const targets[PLM_FIBER_CLI_OPTIONS] = {&c->eccentricity, &c->eta, c->sigma_a, &c->beta_m_deg,
                                                  &c->beta_n_deg, c->medulla_axes, c->medulla_centre,
                                                  c->medulla_reflectance, &c->lobes};
    for (int i = 0; i < PLM_FIBER_CLI_OPTIONS; ++i)
        plm_option_param(&opts[i], &c->text[i], &plm_fiber_param_block, fields[i], targets[i], metavars[i]);
    opts[PLM_FIBER_CLI_OPTIONS - 1].hi = max_lobes; /* what the command can trace */
}

int plm_fiber_cli_params(const plm_fiber_cli *c, const char *command, plm_fiber_params *p)
{
    plm_fiber_params_default(p);
    p->eccentricity = c->eccentricity;
    p->eta = c->eta;
    p->sigma_a = rgb_make(c->sigma_a[0], c->sigma_a[1], c->sigma_a[2]);
    p->beta_m = plm_radians(c->beta_m_deg);
    p->beta_n = plm_radians(c->beta_n_deg);
    p->medulla_a = c->medulla_axes[0];
    p->medulla_b = c->medulla_axes[1];
    p->medulla_ca = c->medulla_centre[0];
    p->medulla_cb = c->medulla_centre[1];
    p->medulla_reflectance = rgb_make(c->medulla_reflectance[0], c->medulla_reflectance[1], c->medulla_reflectance[2]);
    p->lobes = c->lobes;
    plm_error err;
    if (plm_fiber_params_validate(p, &err) != PLM_OK) {
        fprintf(stderr, "error: %s: %s\n", command, err.message);
        return 0;
    }
    return 1;
}

/* Writes the rows of one stdin line: exactly p->lobes, zeros after the last lobe. */
static void write_lobes(FILE *out, const plm_fiber_params *p, const plm_fiber_lobe *lobes, int n)
{
    for (int k = 0; k < p->lobes; ++k) {
        if (k < n) {
            vec3 d = lobes[k].dir;
            rgb t = lobes[k].throughput;
            /* + 0.0 prints -0 as 0 */
            fprintf(out, "%d,%.9g,%.9g,%.9g,%.9g,%.9g\n", k, plm_degrees(plm_safe_asin(d.z)) + 0.0,
                    plm_degrees(atan2(d.y, d.x)) + 0.0, t.r, t.g, t.b);
        } else {
            fprintf(out, "%d,0,0,0,0,0\n", k);
        }
    }
}

/* Traces each stdin line into out; returns 0, or 2 after an error message. */
static int trace_lines(const plm_fiber_params *p, plm_rng *rng, FILE *out)
{
    const char *cmd = "plumage probe fiber";
    static plm_fiber_lobe lobes[PLM_FIBER_MAX_LOBES];
    long line = 0;
    double v[3];
    int got;
    while ((got = plm_read_numbers(stdin, cmd, &line, v, 3)) == 1) {
        if (!(v[0] > -90.0 && v[0] < 90.0) || !(v[2] >= -1.0 && v[2] <= 1.0)) {
            fprintf(stderr,
                    "error: %s: stdin line %ld: theta %g must be in (-90, 90) degrees and h %g in [-1, 1]\n", cmd,
                    line, v[0], v[2]);
            return 2;
        }
        vec3 wo = plm_fiber_direction(plm_radians(v[0]), plm_radians(v[1]));
        write_lobes(out, p, lobes, plm_fiber_trace(p, wo, v[2], rng, lobes));
    }
    return got < 0 ? 2 : 0;
}

int probe_fiber(int argc, char **argv)
{
    static const plm_command_help help = {
        "plumage probe fiber [options] < directions",
        "Traces light into the fiber from view direction (theta, phi) at entry offset h and prints\n"
        "its lobes. stdin: one \"theta phi h\" per line (degrees: theta = asin(w.axis) in (-90, 90),\n"
        "phi = atan2(w.e3, w.e2); h in [-1, 1] across the silhouette; see docs/fiber.md).\n"
        "stdout: lobe,theta_out,phi_out,throughput_r,throughput_g,throughput_b with exactly --lobes rows\n"
        "per line (rows after the last lobe are zeros). Deterministic without a medulla; with one,\n"
        "--seed fixes the diffuse bounces."};
    plm_fiber_cli fc;
    plm_option opts[PLM_FIBER_CLI_OPTIONS + 1];
    plm_fiber_cli_options(&fc, opts, PLM_FIBER_MAX_LOBES);
    int seed = 1;
    opts[PLM_FIBER_CLI_OPTIONS] = (plm_option){"--seed", PLM_OPT_INT, &seed, 1, 0, 2147483647, NULL, "N",
                                               "random seed for the medulla's bounces; default 1", 0};
    int rc = plm_parse_options(&help, argc, argv, 1, opts, PLM_FIBER_CLI_OPTIONS + 1, NULL, 0, NULL);
    if (rc)
        return rc == 1 ? 0 : 2;
    plm_fiber_params p;
    if (!plm_fiber_cli_params(&fc, "plumage probe fiber", &p))
        return 2;
    plm_rng rng;
    plm_rng_seed(&rng, (uint64_t)seed, 0);
    /* Rows wait in a temporary file so a bad line leaves no partial output. */
    FILE *out = tmpfile();
    if (!out) {
        fprintf(stderr, "error: plumage probe fiber: cannot create a temporary file\n");
        return 2;
    }
    fprintf(out, "lobe,theta_out,phi_out,throughput_r,throughput_g,throughput_b\n");
    int status = trace_lines(&p, &rng, out);
    if (status == 0) {
        rewind(out);
        char buf[65536];
        size_t n;
        while ((n = fread(buf, 1, sizeof buf, out)) > 0)
            fwrite(buf, 1, n, stdout);
    }
    fclose(out);
    return status;
}
