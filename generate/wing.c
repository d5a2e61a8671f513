/* The wing layout (generate/wing.h): rows of flight feathers and coverts on
 * a three-bone skeleton, settled onto one another in dorsal order. The
 * reasoning behind the rows, the roll and the settling is in
 * docs/layouts.md. */
#include "generate/wing.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/rng.h"
#include "generate/layout_parts.h"

const char *const plm_wing_row_names[PLM_WING_ROWS] = {
    "primary",       "secondary", "tertial",        "greater_covert",   "median_covert", "lesser_covert",
    "alula",         "primary_covert", "marginal_covert", "under_covert", "speculum"};

int plm_wing_row_fallback(int row)
{
    static const int fallback[PLM_WING_ROWS] = {
        -1, -1, PLM_WING_SECONDARY, PLM_WING_SECONDARY, PLM_WING_SECONDARY, PLM_WING_SECONDARY, PLM_WING_SECONDARY,
        PLM_WING_GREATER_COVERT, PLM_WING_LESSER_COVERT, PLM_WING_MEDIAN_COVERT, PLM_WING_SECONDARY};
    return row >= 0 && row < PLM_WING_ROWS ? fallback[row] : -1;
}

/* The skeleton of the wing at a fold: shoulder, elbow, wrist and hand tip in
 * the wing plane, and the bones' directions. Spread, the bones line up along
 * +x (the hand swept back); folded, the humerus points back, the forearm
 * forward and the hand back again, as a perched bird's wing. */
typedef struct wing_skeleton {
    vec3 joint[4];    /* shoulder, elbow, wrist, hand tip */
    double angle[3];  /* humerus, forearm, hand: radians from +x toward +y (forward) */
    double spread[3]; /* the same bones' angles with the wing spread */
    int np, ns, nt;   /* primaries, secondaries, tertials: the folded wing's stack */
    double chord;     /* layout units */
    double tissue;    /* how high the folded wing's leading edge stands over the bones (WING_FOLDED_TISSUE) */
} wing_skeleton;

static vec3 planar(double angle) { return v3(cos(angle), sin(angle), 0.0); }
static double lerp(double a, double b, double t) { return a + (b - a) * t; }

/* Folded, the rows of coverts lie each on the roots of the row behind it,
 * so the wing is thickest at its leading edge, as a bird's is: the skin
 * ahead of the bones, the leading edge's tissue, rises from them to this
 * share of the chord at the front marginal row (WING_FOLDED_EDGE chords
 * ahead of the bones), and reaches under the marginal coverts' tips
 * (WING_SKIN_FOLDED). On the flat skin the front rows rested on the rows
 * behind them alone, their tips in the air over the leading edge. */
#define WING_FOLDED_TISSUE 0.12
#define WING_FOLDED_EDGE 0.34

static wing_skeleton skeleton_of(const plm_wing_params *p, double span, double chord, int np, int ns, int nt)
{
    /* Bone proportions of a typical wing: humerus, forearm, hand about 3 : 4 : 3. */
    static const double share[3] = {0.29, 0.39, 0.32};
    static const double folded[3] = {-55.0, 85.0, -82.0};
    double bones = fmax(span - 0.85 * 1.4 * chord, 0.3 * span);
    wing_skeleton w = {.np = np, .ns = ns, .nt = nt, .chord = chord, .tissue = p->fold * WING_FOLDED_TISSUE * chord};
    w.spread[0] = 0.0;
    w.spread[1] = 0.0;
    w.spread[2] = -p->sweep;
    w.joint[0] = v3(0, 0, 0);
    for (int b = 0; b < 3; ++b) {
        w.angle[b] = lerp(w.spread[b], plm_radians(folded[b]), p->fold);
        w.joint[b + 1] = v3_madd(w.joint[b], planar(w.angle[b]), share[b] * bones);
    }
    return w;
}

/* A point a fraction t along bone b, moved `forward` toward the leading edge. */
static vec3 on_bone(const wing_skeleton *w, int b, double t, double forward)
{
    vec3 p = v3_add(v3_scale(w->joint[b], 1.0 - t), v3_scale(w->joint[b + 1], t));
    return v3_madd(p, planar(w->angle[b] + 0.5 * PLM_PI), forward);
}

#define WING_BAND_HAND 0.2 /* how far out along the hand a band reaches */
#define WING_BAND_SHOULDER 1.98 /* and how far in: 0 wrist, 1 elbow, 2 shoulder */

/* Folded, the humerus lies under the body's feathers, and what lies ahead
 * of it is the forearm's band of coverts: a band's part along the humerus
 * moves, as the wing folds, onto the forearm's line extended past the
 * elbow, over the tertials' bases, this share of its length (at its full
 * length the rows covered the tertials). Likewise a band's part along the
 * hand, which folds back under the forearm's feathers: onto the forearm's
 * line extended a little ahead of the wrist, rounding the bend of the wing
 * (along the hand it hung below the wrist as a tail of coverts). Bands
 * overlapping one another piled up into a heap of coverts. */
#define WING_FOLDED_HUMERUS 0.7
#define WING_FOLDED_HAND 0.3

/* A point `along` the arm (-WING_BAND_HAND out along the hand, 0 the wrist,
 * 1 the elbow, 2 the shoulder), `forward` ahead of its bone, on the tissue
 * of the folded wing's leading edge. */
static vec3 on_arm(const wing_skeleton *sk, double fold, double along, double forward)
{
    int bone = along < 0.0 ? 2 : along < 1.0 ? 1 : 0;
    double t = bone == 2 ? -along : bone == 1 ? 1.0 - along : 2.0 - along;
    vec3 p = on_bone(sk, bone, plm_clamp(t, 0.0, 1.0), forward);
    if (bone != 1) {
        vec3 back = v3_sub(sk->joint[1], sk->joint[2]); /* wrist to elbow */
        vec3 q = bone == 0 ? v3_madd(on_bone(sk, 1, 0.0, forward), back, (along - 1.0) * WING_FOLDED_HUMERUS)
                           : v3_madd(on_bone(sk, 1, 1.0, forward), back, along * WING_FOLDED_HAND);
        p = v3_add(v3_scale(p, 1.0 - fold), v3_scale(q, fold));
    }
    /* The tissue thins toward the bend of the wing and over the tertials, where the rows end. */
    double ends = along < 0.0 ? 1.0 + along / WING_BAND_HAND : 1.0 - (along - 1.0) / (WING_BAND_SHOULDER - 1.0);
    p.z += sk->tissue * plm_clamp(forward / (WING_FOLDED_EDGE * sk->chord), 0.0, 1.0) * plm_clamp(ends, 0.0, 1.0);
    return p;
}

/* Folded, the flight feathers lie in one stack, from the innermost tertial
 * on top (toward the bird's back, -x) to the outermost primary at the
 * bottom, each a little steeper than the one above (degrees below straight
 * back): each feather's narrow outer vane lies over the broad inner vane of
 * the one below, the secondaries' tips step down and forward, and the
 * primaries reach past them to the wing's point. */
#define WING_FAN_TOP -16.0
#define WING_FAN_BOTTOM 10.0

/* Folded, a band's coverts point this much further down (toward the
 * trailing edge) than the flight feathers beneath them: each lies over the
 * roots of the rows behind it, placed before it, as on the spread wing. Along
 * the rows, pointing back up toward the leading edge, each row's tips lay
 * under the next row's roots and lifted them like scales. */
#define WING_FOLDED_SLANT 30.0

/* The folded direction at stack position s (0 the top, the innermost
 * tertial; nt + ns + np - 1 the outermost primary; fractions between). */
static double folded_fan(const wing_skeleton *sk, double s)
{
    double last = sk->nt + sk->ns + sk->np - 1;
    return -90.0 + lerp(WING_FAN_TOP, WING_FAN_BOTTOM, plm_clamp(s / last, 0.0, 1.0));
}

/* The stack position of the flight feather rooted `along` the arm (as a
 * band's: from -WING_BAND_HAND on the hand over the wrist 0 and the elbow
 * 1 toward the shoulder 2), so that the coverts over it lie as it does. */
static double stack_at(const wing_skeleton *sk, double along)
{
    if (along >= 1.0) /* the tertials, on the humerus's outer quarter */
        return (sk->nt - 1) * plm_clamp(1.0 - (along - 1.0) / 0.25, 0.0, 1.0);
    if (along >= 0.0) /* the secondaries, wrist (the lowest) to elbow */
        return sk->nt + (sk->ns - 1) * (1.0 - along);
    return sk->nt + sk->ns - 1 - along / 0.12 * 0.5; /* the hand: toward the inner primaries */
}

/* Rows of lesser and marginal coverts, and how many coverts a row of them has. */
#define WING_LESSER_ROWS 3
#define WING_MARGINAL_ROWS 2
#define WING_BAND_COUNT(ns, nt) (3 * ((ns) + (nt)))
#define WING_MARGINAL_COUNT(band) ((band) * 2 / 3) /* as dense over their shorter reach */

/* One feather of a row as the wing builds it. */
typedef struct wing_feather {
    int row;          /* its plm_wing_row */
    int species;      /* the row whose species it takes (the speculum's for the outer secondaries) */
    int under;        /* an under-wing covert: it faces down and lies below the wing */
    vec3 root;
    double direction; /* radians in the wing plane */
    double length;    /* layout units */
} wing_feather;

/* Piecewise-linear ramp through (u, value) points. */
static double ramp(const double (*pts)[2], int n, double u)
{
    int k = 0;
    while (k + 2 < n && u > pts[k + 1][0])
        ++k;
    double t = plm_clamp((u - pts[k][0]) / (pts[k + 1][0] - pts[k][0]), 0.0, 1.0);
    return lerp(pts[k][1], pts[k + 1][1], t);
}

/* Direction of a feather: its angle on the spread wing, turned toward the
 * body axis (straight back) as the wing folds. */
static double fold_direction(const plm_wing_params *p, double spread, double folded)
{
    return lerp(spread, plm_radians(folded), p->fold);
}

typedef struct wing_rows {
    wing_feather *f;
    int count, capacity;
    int flight; /* how many flight feathers: they come first, and the rest settle onto them */
} wing_rows;

static void add_feather(wing_rows *w, int row, vec3 root, double direction, double length)
{
    wing_feather *f = &w->f[w->count++];
    f->row = row;
    f->species = row;
    f->under = 0;
    f->root = root;
    f->direction = direction;
    f->length = length;
}

/* A band of small coverts along the arm from the base of the hand, over the
 * wrist, forearm and humerus to the shoulder, n of them `forward` ahead of
 * the bones (less ahead of the hand, whose leading edge is narrower),
 * fanning from 75 to 110 degrees behind them; `offset` (0 or 0.5 of a
 * spacing) lets one row lie over the gaps of the row behind. */
/* The marginal coverts reach a third of the way up the humerus: nearer the
 * shoulder its leading edge lies under the body's feathers, and folded, a
 * row along the whole humerus ran round the wing's inner end like a collar. */
#define WING_MARGINAL_REACH 1.35

/* Small coverts grow from follicles scattered about their rows, not on a
 * lattice: each root moves up to `WING_BAND_JITTER` of a spacing along the
 * band and of the rows' spacing forward, and its length and direction vary. */
#define WING_BAND_JITTER 0.35

static void add_band(const plm_wing_params *p, const wing_skeleton *sk, wing_rows *w, int row, int n, double offset,
                     double forward, double length, double reach)
{
    plm_rng rng; /* each band its own stream, named by its row and how far ahead it lies */
    plm_rng_seed(&rng, plm_hash64(p->seed, (uint64_t)row, (uint64_t)(forward * 1e6)), PLM_LAYOUT_STREAM_PLACE);
    double spacing = (reach + WING_BAND_HAND) / (n - 1);
    int first = w->count;
    for (int j = 0; j < n; ++j) {
        double u = (j + offset) / (n - 1), jitter[4];
        for (int k = 0; k < 4; ++k)
            jitter[k] = 2.0 * plm_rng_uniform(&rng) - 1.0;
        double along = lerp(-WING_BAND_HAND, reach, u) + WING_BAND_JITTER * spacing * jitter[0];
        double fan = (along + WING_BAND_HAND) / (WING_BAND_SHOULDER + WING_BAND_HAND);
        int bone = along < 0.0 ? 2 : along < 1.0 ? 1 : 0;
        double ahead = forward * (1.0 + 0.1 * jitter[1]);
        if (bone == 2)
            ahead *= 1.0 + 0.8 * along / WING_BAND_HAND;
        add_feather(w, row, on_arm(sk, p->fold, along, ahead),
                    fold_direction(p, sk->spread[bone] - plm_radians(lerp(75.0, 110.0, fan) + 8.0 * jitter[2]),
                                   folded_fan(sk, stack_at(sk, along)) + WING_FOLDED_SLANT),
                    length * (1.0 + 0.15 * jitter[3]));
    }
    /* Folded, a row's coverts point back along it, and each lies over the
     * root of the one behind it, as shingles: they settle from the back end
     * forward. Settled from the wrist back, each one's base rode up on the
     * one in front, and the back end of every row hung in the air over the
     * tertials. */
    for (int a = first, b = w->count - 1; p->fold > 0.5 && a < b; ++a, --b) {
        wing_feather t = w->f[a];
        w->f[a] = w->f[b];
        w->f[b] = t;
    }
}

/* A covert over (or under) the base of each flight feather,
 * `forward` ahead of its root, as long as the given shares of the feather. */
static void add_over_flight(const wing_skeleton *sk, wing_rows *w, int primary_row, int secondary_row,
                            double forward, double primary_share, double secondary_share)
{
    for (int i = 0; i < w->flight; ++i) {
        const wing_feather *r = &w->f[i];
        int primary = r->row == PLM_WING_PRIMARY, bone = primary ? 2 : 1;
        add_feather(w, primary ? primary_row : secondary_row,
                    v3_madd(r->root, planar(sk->angle[bone] + 0.5 * PLM_PI), forward), r->direction,
                    (primary ? primary_share : secondary_share) * r->length);
    }
}

/* Every feather of the wing's dorsal side in dorsal order, bottom first:
 * primaries from the outermost in (each proximal feather lies over the next
 * distal one), then the secondaries from the wrist in and the tertials; then
 * the primary and greater coverts, the alula (the coverts at the bend of the
 * wing cover its base), and the other covert rows back to front (median,
 * three rows of lesser coverts, two of marginal coverts over the leading
 * edge). Lengths in layout units. */
static void build_dorsal(const plm_wing_params *p, const wing_skeleton *sk, double chord, double primary, int np,
                         int ns, int nt, wing_rows *w)
{
    /* Primaries lengthen from about the secondaries' length at the wrist to
     * the longest three quarters of the way out; the outermost is shorter. */
    const double primary_ramp[4][2] = {{0.0, 1.05 * chord}, {0.75, primary}, {0.9, 0.98 * primary},
                                       {1.0, 0.86 * primary}};
    for (int i = np - 1; i >= 0; --i) {
        double u = np > 1 ? (double)i / (np - 1) : 1.0;
        add_feather(w, PLM_WING_PRIMARY, on_bone(sk, 2, 0.12 + 0.88 * u, 0.0),
                    fold_direction(p, sk->spread[2] - plm_radians(lerp(70.0, 14.0, u)), folded_fan(sk, nt + ns + i)),
                    ramp(primary_ramp, 4, u));
    }
    for (int j = 0; j < ns; ++j) {
        double u = ns > 1 ? (double)j / (ns - 1) : 0.0;
        add_feather(w, PLM_WING_SECONDARY, on_bone(sk, 1, 1.0 - 0.95 * u, 0.0),
                    fold_direction(p, sk->spread[1] - plm_radians(lerp(82.0, 100.0, u)),
                                   folded_fan(sk, nt + ns - 1 - j)),
                    chord * (1.0 - 0.08 * u));
        if (j < p->speculum)
            w->f[w->count - 1].species = PLM_WING_SPECULUM;
    }
    for (int k = 0; k < nt; ++k) {
        double u = nt > 1 ? (double)k / (nt - 1) : 0.0;
        add_feather(w, PLM_WING_TERTIAL, on_bone(sk, 0, 0.97 - 0.25 * u, 0.0),
                    fold_direction(p, sk->spread[0] - plm_radians(lerp(102.0, 112.0, u)), folded_fan(sk, nt - 1 - k)),
                    chord * (0.8 - 0.2 * u));
    }
    w->flight = w->count;
    add_over_flight(sk, w, PLM_WING_PRIMARY_COVERT, PLM_WING_GREATER_COVERT, 0.04 * chord, 0.3, 0.42);
    /* The alula at the bend of the wing, on the primary coverts' bases along
     * the hand's leading edge: the longest, on top, along it, the shorter
     * ones below fanning a little back over the coverts. */
    for (int a = 2; a >= 0; --a)
        add_feather(w, PLM_WING_ALULA, on_bone(sk, 2, 0.04 + 0.02 * a, 0.015 * chord),
                    fold_direction(p, sk->spread[2] - plm_radians(4.0 * a), folded_fan(sk, nt + ns + a)),
                    (0.3 - 0.04 * a) * chord);
    /* Median coverts over the secondaries' coverts, lesser coverts toward the
     * leading edge, each row over the gaps of the one behind, and the
     * marginal coverts, the smallest, along the leading edge itself. */
    add_band(p, sk, w, PLM_WING_MEDIAN_COVERT, 2 * (ns + nt), 0.0, 0.14 * chord, 0.24 * chord,
             WING_BAND_SHOULDER);
    int band = WING_BAND_COUNT(ns, nt);
    for (int sub = 0; sub < WING_LESSER_ROWS; ++sub)
        add_band(p, sk, w, PLM_WING_LESSER_COVERT, band, 0.5 * (sub & 1), (0.18 + 0.04 * sub) * chord,
                 (0.16 - 0.015 * sub) * chord, WING_BAND_SHOULDER);
    for (int sub = 0; sub < WING_MARGINAL_ROWS; ++sub)
        add_band(p, sk, w, PLM_WING_MARGINAL_COVERT, WING_MARGINAL_COUNT(band), 0.5 * ((sub + WING_LESSER_ROWS) & 1),
                 (0.18 + 0.04 * (WING_LESSER_ROWS + sub)) * chord, 0.1 * chord, WING_MARGINAL_REACH);
}

/* The under-wing coverts in the order they settle, from the flight feathers
 * down: under greater coverts under the bases of primaries and secondaries,
 * a median row, two lesser rows and the marginal coverts under the leading
 * edge, each row lying below the one behind it as seen from beneath. */
static void build_ventral(const plm_wing_params *p, const wing_skeleton *sk, double chord, int ns, int nt,
                          wing_rows *w)
{
    int first = w->count;
    add_over_flight(sk, w, PLM_WING_UNDER_COVERT, PLM_WING_UNDER_COVERT, 0.03 * chord, 0.3, 0.45);
    int band = WING_BAND_COUNT(ns, nt);
    for (int sub = 0; sub < 4; ++sub)
        add_band(p, sk, w, PLM_WING_UNDER_COVERT, sub ? band : ns + nt, 0.5 * (sub & 1),
                 (0.10 + 0.075 * sub) * chord, (0.28 - 0.05 * sub) * chord, WING_BAND_SHOULDER);
    for (int i = first; i < w->count; ++i) { /* the tissue stands on the dorsal side */
        w->f[i].under = 1;
        w->f[i].root.z = 0.0;
    }
}

/* A height field over the wing plane: the highest z of what lies beneath. */
typedef struct height_grid {
    double x0, y0, cell;
    int nx, ny;
    double *z;
} height_grid;

/* Visits the grid cells whose centres lie in the triangle, with the
 * triangle's height there. mode 0 raises the grid to it; mode 1 returns how
 * far the triangle must rise to clear the grid. */
static double raster(height_grid *g, vec3 a, vec3 b, vec3 c, int mode)
{
    double need = -INFINITY;
    double det = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
    if (fabs(det) < 1e-300)
        return need;
    int i0 = (int)floor((fmin(a.x, fmin(b.x, c.x)) - g->x0) / g->cell), i1 = (int)ceil((fmax(a.x, fmax(b.x, c.x)) - g->x0) / g->cell);
    int j0 = (int)floor((fmin(a.y, fmin(b.y, c.y)) - g->y0) / g->cell), j1 = (int)ceil((fmax(a.y, fmax(b.y, c.y)) - g->y0) / g->cell);
    for (int j = j0 < 0 ? 0 : j0; j <= j1 && j < g->ny; ++j)
        for (int i = i0 < 0 ? 0 : i0; i <= i1 && i < g->nx; ++i) {
            double x = g->x0 + (i + 0.5) * g->cell, y = g->y0 + (j + 0.5) * g->cell;
            double l1 = ((x - a.x) * (c.y - a.y) - (c.x - a.x) * (y - a.y)) / det;
            double l2 = ((b.x - a.x) * (y - a.y) - (x - a.x) * (b.y - a.y)) / det;
            if (l1 < 0.0 || l2 < 0.0 || l1 + l2 > 1.0)
                continue;
            double z = a.z + l1 * (b.z - a.z) + l2 * (c.z - a.z);
            double *cellz = &g->z[(size_t)j * g->nx + i];
            if (mode == 0)
                *cellz = fmax(*cellz, z);
            else
                need = fmax(need, *cellz - z);
        }
    return need;
}

/* The instance's triangles rastered (raster's mode), leaving out those
 * nearer its root than `embedded` (mm along its rachis). */
static double raster_instance(height_grid *g, const plm_layout_instance *in, const plm_layout_extent *e, int mode,
                              double embedded)
{
    double need = -INFINITY;
    for (int k = 0; k < 2; ++k) {
        const plm_mesh *m = &e->mesh[k];
        for (int t = 0; t < m->triangle_count; ++t) {
            const uint32_t *v = m->indices + 3 * t;
            if (m->positions[3 * v[0] + 1] < embedded && m->positions[3 * v[1] + 1] < embedded &&
                m->positions[3 * v[2] + 1] < embedded)
                continue;
            vec3 a = plm_layout_apply(in, m->positions + 3 * v[0]), b = plm_layout_apply(in, m->positions + 3 * v[1]),
                 c = plm_layout_apply(in, m->positions + 3 * v[2]);
            need = fmax(need, raster(g, a, b, c, mode));
        }
    }
    return need;
}

/* The instance pitched by `angle` about its feather frame's x axis at the
 * root: the tip rises for positive angles. The frame turns as a whole, its
 * rachis and dorsal axes keeping their lengths (a folded wing's feathers are
 * flattened along the dorsal one). */
static void pitch(plm_layout_instance *in, double angle)
{
    double c = cos(angle), s = sin(angle), lt = 0.0, lz = 0.0;
    for (int r = 0; r < 3; ++r) {
        lt += in->m[r][1] * in->m[r][1];
        lz += in->m[r][2] * in->m[r][2];
    }
    double k = sqrt(lt / lz);
    for (int r = 0; r < 3; ++r) {
        double t = in->m[r][1], z = in->m[r][2] * k;
        in->m[r][1] = c * t + s * z;
        in->m[r][2] = (c * z - s * t) / k;
    }
}

/* Settles a feather onto what lies beneath it. Pitched about its root in
 * whole degrees, each time raised just `clearance` clear of the height field
 * (never below where it started), it keeps the pitch that brings the middle
 * of its rachis lowest, as a weight settles: onto two contacts, near its base
 * and further along, instead of balancing on its highest contact with the
 * rest in the air. Pitches at which it touches nothing are not resting; a
 * feather touching nothing stays flat. The range keeps coverts lying along
 * the wing: steeper, a row's bases would stand up off it like a comb. */
#define WING_PITCH_DOWN 8
#define WING_PITCH_UP 10

static void settle(height_grid *g, plm_layout_instance *in, const plm_layout_extent *e, double clearance,
                   double embedded)
{
    const float middle[3] = {0.0f, (float)(0.5 * e->length), 0.0f};
    plm_layout_instance flat = *in;
    double lowest = INFINITY;
    for (int degrees = -WING_PITCH_DOWN; degrees <= WING_PITCH_UP; ++degrees) {
        plm_layout_instance t = flat;
        pitch(&t, plm_radians(degrees));
        double need = raster_instance(g, &t, e, 1, embedded);
        if (need == -INFINITY && degrees != 0)
            continue;
        t.m[2][3] += fmax(need, 0.0) + clearance;
        double z = plm_layout_apply(&t, middle).z;
        if (z < lowest) {
            lowest = z;
            t.lift = plm_radians(degrees);
            *in = t;
        }
    }
}

/* The instance mirrored through the wing plane (z negated). */
static plm_layout_instance mirrored(const plm_layout_instance *in)
{
    plm_layout_instance m = *in;
    for (int c = 0; c < 4; ++c)
        m.m[2][c] = -m.m[2][c];
    return m;
}

/* The frame's linear part orthonormal (a rotation or a reflection), or all zero. */
static plm_result check_frame(const double f[3][4], int *identity, plm_error *err)
{
    *identity = 1;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c)
            *identity &= f[r][c] == 0.0;
    for (int a = 0; a < 3 && !*identity; ++a)
        for (int b = a; b < 3; ++b) {
            double dot = f[0][a] * f[0][b] + f[1][a] * f[1][b] + f[2][a] * f[2][b];
            if (!(fabs(dot - (a == b)) < 1e-6))
                return plm_fail(err, PLM_ERR_INVALID,
                                "wing: frame's columns %d and %d have dot product %g; they must be orthonormal", a, b,
                                dot);
        }
    return PLM_OK;
}

/* Takes an instance from wing space through the shoulder frame. */
static void apply_frame(const double f[3][4], plm_layout_instance *in)
{
    double m[3][4];
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c)
            m[r][c] = f[r][0] * in->m[0][c] + f[r][1] * in->m[1][c] + f[r][2] * in->m[2][c] + (c == 3 ? f[r][3] : 0.0);
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c)
            in->m[r][c] = m[r][c];
}

static plm_result check_params(const plm_wing_params *p, int np, int ns, int nt, double span, double chord,
                               plm_error *err)
{
    if (np < 2 || np > 12)
        return plm_fail(err, PLM_ERR_INVALID, "wing: primaries %d is out of range [2, 12]", np);
    if (ns < 2 || ns > 24)
        return plm_fail(err, PLM_ERR_INVALID, "wing: secondaries %d is out of range [2, 24]", ns);
    if (nt < 1 || nt > 6)
        return plm_fail(err, PLM_ERR_INVALID, "wing: tertials %d is out of range [1, 6]", nt);
    if (p->speculum < 0 || p->speculum > ns)
        return plm_fail(err, PLM_ERR_INVALID, "wing: speculum %d is out of range [0, secondaries %d]", p->speculum,
                        ns);
    if (!(p->fold >= 0.0 && p->fold <= 1.0))
        return plm_fail(err, PLM_ERR_INVALID, "wing: fold %g is out of range [0, 1]", p->fold);
    if (!(p->sweep >= 0.0 && p->sweep <= plm_radians(45.0)))
        return plm_fail(err, PLM_ERR_INVALID, "wing: sweep %g degrees is out of range [0, 45]", plm_degrees(p->sweep));
    if (!(chord <= span))
        return plm_fail(err, PLM_ERR_INVALID, "wing: chord %g is out of range (0, span %g]", chord, span);
    return PLM_OK;
}

/* The parameters with their defaults filled in, checked. */
static plm_result resolve(const plm_wing_params *p, int *np, int *ns, int *nt, double *span, double *chord,
                          int *identity, plm_error *err)
{
    *np = p->primaries ? p->primaries : 10;
    *ns = p->secondaries ? p->secondaries : 12;
    *nt = p->tertials ? p->tertials : 3;
    *span = p->span > 0.0 ? p->span : 1.0;
    *chord = p->chord > 0.0 ? p->chord : 0.3 * *span;
    plm_result rc = check_params(p, *np, *ns, *nt, *span, *chord, err);
    return rc == PLM_OK ? check_frame(p->frame, identity, err) : rc;
}

/* A height field around every root, a flight feather's length each way. */
static plm_result make_grid(const wing_rows *w, double reach, double cell, height_grid *g, plm_error *err)
{
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (int i = 0; i < w->count; ++i) {
        lo[0] = fmin(lo[0], w->f[i].root.x - reach);
        lo[1] = fmin(lo[1], w->f[i].root.y - reach);
        hi[0] = fmax(hi[0], w->f[i].root.x + reach);
        hi[1] = fmax(hi[1], w->f[i].root.y + reach);
    }
    g->cell = cell;
    g->x0 = lo[0];
    g->y0 = lo[1];
    g->nx = (int)ceil((hi[0] - lo[0]) / cell);
    g->ny = (int)ceil((hi[1] - lo[1]) / cell);
    g->z = malloc(sizeof(double) * (size_t)g->nx * (size_t)g->ny);
    if (!g->z)
        return plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory for a wing's height field");
    for (size_t i = 0; i < (size_t)g->nx * (size_t)g->ny; ++i)
        g->z[i] = -INFINITY;
    return PLM_OK;
}

/* The skin's front edge ahead of humerus and forearm, in chords: behind the
 * front two rows of marginal coverts' roots (0.30 and 0.34), which cover it
 * (at 0.32 it showed between the front row's roots). The strip ends a tenth
 * of the way along the hand, narrowing to WING_SKIN_HAND: further out the
 * primaries' and their coverts' bases lie on the hand with no skin between
 * (a strip along the whole hand showed along its leading edge). */
#define WING_SKIN_ARM 0.28
#define WING_SKIN_HAND 0.015
/* Along the inner humerus, beyond the marginal coverts' reach: under the front lesser row (0.26). */
#define WING_SKIN_HUMERUS 0.21
#define WING_SKIN_END 2.1
/* Folded, the front edge along the forearm: under the marginal coverts' tips, behind the front row's roots;
 * elsewhere as much further forward (all along the arm, it showed beyond the marginal coverts' reach). */
#define WING_SKIN_FOLDED 0.33
#define WING_SKIN_POINTS (3 * 16 + 1) /* along the strip: 16 per bone */

/* A point of the skin's strip: along the arm (0 shoulder, 1 elbow, 2 wrist,
 * then along the hand), at its back edge (the bones) or its front edge. */
static vec3 skin_point(const wing_skeleton *sk, double fold, double along, int front, double chord)
{
    int b = along >= 2.0 ? 2 : (int)along;
    double t = along - b, end = WING_SKIN_END - 2.0;
    double ahead = b == 1   ? WING_SKIN_ARM
                   : b == 2 ? lerp(WING_SKIN_ARM, WING_SKIN_HAND, fmin(t / end, 1.0))
                            : lerp(WING_SKIN_HUMERUS, WING_SKIN_ARM, plm_clamp((t - 0.6) / 0.4, 0.0, 1.0));
    return on_arm(sk, fold, 2.0 - along, front ? (ahead + fold * (WING_SKIN_FOLDED - WING_SKIN_ARM)) * chord : 0.0);
}

/* The skin raised into the height field, so that a folded wing's coverts
 * settle onto the leading edge's tissue. */
static void raster_skin(height_grid *g, const wing_skeleton *sk, double fold, double chord)
{
    for (int k = 0; k + 1 < WING_SKIN_POINTS; ++k) {
        vec3 q[4];
        for (int v = 0; v < 4; ++v)
            q[v] = skin_point(sk, fold, WING_SKIN_END * (k + v / 2) / (WING_SKIN_POINTS - 1), v & 1, chord);
        raster(g, q[0], q[2], q[1], 0);
        raster(g, q[1], q[2], q[3], 0);
    }
}

/* Roll of every wing feather about its rachis, raising its distal (leading)
 * vane: where neighbours overlap, the proximal one's raised vane lies over
 * the distal one's lowered vane, as on a real wing. */
#define WING_ROLL_DEGREES 10.0
/* Folded, the feathers lie one on another, in order as they are placed: a
 * full roll raised each one's leading vane over the next a feather's width
 * further, and the stack of them a third of the chord high. */
#define WING_FOLDED_ROLL 2.0

/* How much flatter a folded wing's feathers lie than they were generated. */
#define WING_FOLDED_FLATTEN 0.1

/* Folded, the feathers' bases lie in the wing's tissue at the bones, side by
 * side, not on one another: this share of each feather, from its root, is
 * not stacked. Stacked base on base, every primary lifted the next by its
 * calamus and the stack stood a quarter of the chord high at the hand. */
#define WING_FOLDED_EMBEDDED 0.2

/* What placing needs besides the feather: the prototypes' extents, the
 * variation, and the two height fields, over the dorsal side and (mirrored)
 * under the ventral side. */
typedef struct wing_placer {
    const plm_wing_params *p;
    const plm_layout_extent *ext;
    plm_layout_ranges var;
    int variants;
    double chord;
    height_grid above, below;
} wing_placer;

/* Places feather f (the i-th in settling order) as instance `in` of dorsal order `order`. */
static void place(wing_placer *pl, const wing_rows *w, int i, int order, plm_layout_instance *in)
{
    const wing_feather *f = &w->f[i];
    plm_rng rng;
    plm_rng_seed(&rng, plm_hash64(pl->p->seed, (uint64_t)i, 1), PLM_LAYOUT_STREAM_FEATHER);
    int v = (int)(plm_rng_uniform(&rng) * pl->variants);
    in->prototype = f->species * pl->variants + v;
    in->row = f->row;
    in->order = order;
    plm_layout_draw_variation(&rng, &pl->var, in);
    in->lift = 0.0;
    const plm_layout_extent *e = &pl->ext[in->prototype];
    double roll = plm_radians(lerp(WING_ROLL_DEGREES, WING_FOLDED_ROLL, pl->p->fold));
    vec3 t = planar(f->direction + in->yaw), up = v3(0, 0, 1), x0 = v3_cross(t, up);
    vec3 x = v3_sub(v3_scale(x0, cos(roll)), v3_scale(up, sin(roll)));
    vec3 z = v3_add(v3_scale(x0, sin(roll)), v3_scale(up, cos(roll)));
    /* Folding stacks the flight feathers, each a little above the ones
     * before, so that they overlap in order; the coverts and the alula
     * start from the wing plane and settle onto what lies beneath. */
    double stack = i < w->flight ? pl->p->fold * i * 0.002 * pl->chord : 0.0;
    /* An under-wing covert is placed as a dorsal one, with its feather frame
     * mirrored, in the world mirrored through the wing plane (where it
     * settles onto the flight feathers' undersides from below); mirrored
     * back, its dorsal side faces down and its matrix is a rotation again. */
    if (f->under)
        x = v3_neg(x);
    /* Folded, the feathers lie pressed on one another: flatter, their rachises and the roll lifting the
     * ones above less (stiff, a stack of 25 flight feathers stood a third of the chord high). */
    double flatten = lerp(1.0, WING_FOLDED_FLATTEN, pl->p->fold);
    double clearance = lerp(0.004, 0.001, pl->p->fold) * pl->chord;
    double embedded = pl->p->fold * WING_FOLDED_EMBEDDED * e->length;
    plm_layout_set_matrix(in, x, t, v3_scale(z, flatten), v3_madd(f->root, up, stack),
                          in->scale * f->length / e->length);
    if (f->under) {
        settle(&pl->below, in, e, clearance, embedded);
        raster_instance(&pl->below, in, e, 0, embedded);
        *in = mirrored(in);
        return;
    }
    if (i >= w->flight || pl->p->fold > 0.0)
        settle(&pl->above, in, e, clearance, embedded);
    raster_instance(&pl->above, in, e, 0, embedded);
    plm_layout_instance below = mirrored(in);
    raster_instance(&pl->below, &below, e, 0, embedded);
}

plm_result plm_layout_wing(const plm_wing_params *p, const plm_species *const *rows, plm_layout *out,
                           plm_error *err)
{
    memset(out, 0, sizeof *out);
    if (!rows || !rows[PLM_WING_PRIMARY] || !rows[PLM_WING_SECONDARY])
        return plm_fail(err, PLM_ERR_INVALID, "wing: the primary and secondary rows need a species");
    int np, ns, nt, identity;
    double span, chord;
    plm_result rc = resolve(p, &np, &ns, &nt, &span, &chord, &identity, err);
    if (rc != PLM_OK)
        return rc;
    const plm_species *list[PLM_WING_ROWS];
    for (int r = 0; r < PLM_WING_ROWS; ++r)
        list[r] = rows[r] ? rows[r] : list[plm_wing_row_fallback(r)];

    double primary = 1.4 * chord;
    wing_skeleton sk = skeleton_of(p, span, chord, np, ns, nt);
    wing_rows w = {0};
    /* Flight feathers, coverts above and below their bases, the alula, the median coverts; the bands of
     * 2 (ns + nt) coverts above (lesser, marginal) and below (three), and the under-wing median row. */
    int band = WING_BAND_COUNT(ns, nt);
    w.capacity = 3 * (np + ns + nt) + 3 + 2 * (ns + nt) + (WING_LESSER_ROWS + WING_MARGINAL_ROWS + 3) * band + ns + nt;
    w.f = malloc(sizeof *w.f * (size_t)w.capacity);
    out->instances = calloc((size_t)w.capacity, sizeof *out->instances);
    plm_layout_extent *ext = NULL;
    wing_placer pl = {.p = p, .variants = p->variants > 0 ? p->variants : 3, .chord = chord};
    rc = w.f && out->instances ? PLM_OK : plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory for a wing");
    if (rc == PLM_OK)
        rc = plm_layout_make_prototypes(list, PLM_WING_ROWS, pl.variants, p->seed, out, &ext, err);
    int dorsal = 0;
    if (rc == PLM_OK) {
        build_dorsal(p, &sk, chord, primary, np, ns, nt, &w);
        dorsal = w.count;
        build_ventral(p, &sk, chord, ns, nt, &w);
        rc = make_grid(&w, primary, chord / 80.0, &pl.above, err);
        if (rc == PLM_OK)
            rc = make_grid(&w, primary, chord / 80.0, &pl.below, err);
    }
    pl.ext = ext;
    pl.var = plm_layout_ranges_of(&p->variation);
    /* The rows' sizes and directions are the wing's shape: variation stays small. */
    pl.var.scale *= 0.3;
    pl.var.yaw *= 0.3;
    /* Dorsal order: the under-wing coverts first, the last to settle (the most ventral) lowest. */
    int ventral = w.count - dorsal;
    for (int i = 0; rc == PLM_OK && i < w.count; ++i) {
        if (i == w.flight && p->fold > 0.0) /* the coverts lie on the flight feathers and the skin */
            raster_skin(&pl.above, &sk, p->fold, chord);
        int order = i < dorsal ? ventral + i : w.count - 1 - i;
        place(&pl, &w, i, order, &out->instances[order]);
        if (!identity)
            apply_frame(p->frame, &out->instances[order]);
    }
    if (rc == PLM_OK)
        out->instance_count = w.count;
    plm_layout_extents_free(ext, out->prototype_count);
    free(pl.above.z);
    free(pl.below.z);
    free(w.f);
    if (rc != PLM_OK)
        plm_layout_free(out);
    return rc;
}

plm_result plm_wing_skin(const plm_wing_params *p, plm_mesh *out, plm_error *err)
{
    memset(out, 0, sizeof *out);
    int np, ns, nt, identity;
    double span, chord;
    plm_result rc = resolve(p, &np, &ns, &nt, &span, &chord, &identity, err);
    if (rc != PLM_OK)
        return rc;
    wing_skeleton sk = skeleton_of(p, span, chord, np, ns, nt);
    int n = WING_SKIN_POINTS;
    out->vertex_count = 2 * n;
    out->triangle_count = 2 * (n - 1);
    out->positions = malloc(sizeof(float) * 3 * (size_t)out->vertex_count);
    out->normals = malloc(sizeof(float) * 3 * (size_t)out->vertex_count);
    out->indices = malloc(sizeof(uint32_t) * 3 * (size_t)out->triangle_count);
    if (!out->positions || !out->normals || !out->indices) {
        plm_mesh_free(out);
        return plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory for a wing's skin");
    }
    const double (*f)[4] = p->frame;
    for (int v = 0; v < out->vertex_count; ++v) {
        vec3 q = skin_point(&sk, p->fold, WING_SKIN_END * (v / 2) / (n - 1), v & 1, chord);
        double x[3] = {q.x, q.y, q.z}, nz[3] = {0, 0, 1};
        for (int r = 0; r < 3; ++r) {
            out->positions[3 * v + r] =
                (float)(identity ? x[r] : f[r][0] * x[0] + f[r][1] * x[1] + f[r][2] * x[2] + f[r][3]);
            out->normals[3 * v + r] = (float)(identity ? nz[r] : f[r][2]);
        }
    }
    for (int k = 0; k + 1 < n; ++k) {
        uint32_t a = (uint32_t)(2 * k), *t = out->indices + 6 * k;
        t[0] = a, t[1] = a + 2, t[2] = a + 1;
        t[3] = a + 1, t[4] = a + 2, t[5] = a + 3;
    }
    return PLM_OK;
}
