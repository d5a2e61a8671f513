// OpenSubdiv adapter behind generate/subdiv.h: Catmull-Clark refinement and
// limit evaluation (Far::TopologyRefiner + Far::PrimvarRefiner) of quad cages.
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <vector>

extern "C" {
#include "generate/subdiv.h"
}
#include "common/adapter_guard.hpp"

using namespace OpenSubdiv;

namespace {

// A primvar of up to PLM_SUBDIV_MAX_WIDTH doubles, in the form OpenSubdiv's
// templates expect (Clear, AddWithWeight).
struct primvar {
    double v[PLM_SUBDIV_MAX_WIDTH];
    void Clear() { std::memset(v, 0, sizeof v); }
    void AddWithWeight(const primvar &src, double w)
    {
        for (int i = 0; i < PLM_SUBDIV_MAX_WIDTH; ++i)
            v[i] += w * src.v[i];
    }
};

typedef Far::TopologyDescriptor descriptor;
typedef Far::PrimvarRefinerReal<double> primvar_refiner;

std::unique_ptr<Far::TopologyRefiner> make_refiner(const plm_subdiv_cage *cage, std::vector<int> &sizes)
{
    sizes.assign((size_t)cage->quad_count, 4);
    descriptor desc;
    desc.numVertices = cage->vertex_count;
    desc.numFaces = cage->quad_count;
    desc.numVertsPerFace = sizes.data();
    desc.vertIndicesPerFace = cage->quads;
    Sdc::Options options;
    // Open boundaries (the vane's edges) end in smooth B-spline curves with
    // their corners held in place.
    options.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER);
    Far::TopologyRefinerFactory<descriptor>::Options factory_options(Sdc::SCHEME_CATMARK, options);
    return std::unique_ptr<Far::TopologyRefiner>(Far::TopologyRefinerFactory<descriptor>::Create(desc, factory_options));
}

plm_result check_cage(const plm_subdiv_cage *cage, plm_error *err)
{
    if (cage->vertex_count < 4 || cage->quad_count < 1 || cage->width < 1 || cage->width > PLM_SUBDIV_MAX_WIDTH)
        return plm_fail(err, PLM_ERR_INVALID, "subdivision cage: %d vertices, %d quads, width %d is not a cage",
                        cage->vertex_count, cage->quad_count, cage->width);
    for (int i = 0; i < 4 * cage->quad_count; ++i)
        if (cage->quads[i] < 0 || cage->quads[i] >= cage->vertex_count)
            return plm_fail(err, PLM_ERR_INVALID, "subdivision cage: quad %d refers to vertex %d of %d", i / 4,
                            cage->quads[i], cage->vertex_count);
    return PLM_OK;
}

std::vector<primvar> load(const double *values, int count, int width)
{
    std::vector<primvar> pv((size_t)count);
    for (int i = 0; i < count; ++i) {
        pv[(size_t)i].Clear();
        std::memcpy(pv[(size_t)i].v, values + (size_t)i * width, sizeof(double) * (size_t)width);
    }
    return pv;
}

} // namespace

static plm_result subdiv_fit(const plm_subdiv_cage *cage, double *values, int iterations, double *residual,
                             plm_error *err)
{
    plm_result rc = check_cage(cage, err);
    if (rc != PLM_OK)
        return rc;
    std::vector<int> sizes;
    std::unique_ptr<Far::TopologyRefiner> refiner = make_refiner(cage, sizes);
    if (!refiner)
        return plm_fail(err, PLM_ERR_INTERNAL, "OpenSubdiv refused the cage (non-manifold topology?)");
    primvar_refiner pr(*refiner);
    int n = cage->vertex_count, w = cage->width;
    std::vector<primvar> target = load(values, n, w), control = target, limit((size_t)n);
    double worst = 0.0;
    // Each pass moves the control points by what the limit still misses; the
    // limit operator's weights sum to one with a dominant centre, so the
    // error shrinks by a constant factor per pass.
    for (int it = 0; it < iterations; ++it) {
        pr.Limit(control, limit);
        worst = 0.0;
        for (size_t i = 0; i < (size_t)n; ++i)
            for (int c = 0; c < w; ++c) {
                double miss = target[i].v[c] - limit[i].v[c];
                control[i].v[c] += miss;
                worst = std::fmax(worst, std::fabs(miss));
            }
    }
    for (int i = 0; i < n; ++i)
        std::memcpy(values + (size_t)i * w, control[(size_t)i].v, sizeof(double) * (size_t)w);
    if (residual)
        *residual = worst;
    return PLM_OK;
}

static plm_result subdiv_refine(const plm_subdiv_cage *cage, const double *values, int level, plm_subdiv_limit *out,
                                plm_error *err)
{
    plm_result rc = check_cage(cage, err);
    if (rc != PLM_OK)
        return rc;
    if (level < 1 || level > 6)
        return plm_fail(err, PLM_ERR_INVALID, "subdivision level %d is out of range [1, 6]", level);
    std::vector<int> sizes;
    std::unique_ptr<Far::TopologyRefiner> refiner = make_refiner(cage, sizes);
    if (!refiner)
        return plm_fail(err, PLM_ERR_INTERNAL, "OpenSubdiv refused the cage (non-manifold topology?)");
    Far::TopologyRefiner::UniformOptions uniform(level);
    uniform.fullTopologyInLastLevel = true; // the limit masks need each vertex's full neighbourhood
    refiner->RefineUniform(uniform);
    primvar_refiner pr(*refiner);
    std::vector<primvar> src = load(values, cage->vertex_count, cage->width), dst;
    for (int l = 1; l <= level; ++l) {
        dst.assign((size_t)refiner->GetLevel(l).GetNumVertices(), primvar());
        pr.Interpolate(l, src, dst);
        src.swap(dst);
    }
    const Far::TopologyLevel &last = refiner->GetLevel(level);
    size_t n = (size_t)last.GetNumVertices();
    std::vector<primvar> pos(n), d1(n), d2(n);
    pr.Limit(src, pos, d1, d2);
    int w = cage->width;
    out->vertex_count = (int)n;
    out->quad_count = last.GetNumFaces();
    out->width = w;
    out->value = (double *)std::malloc(n * w * sizeof(double));
    out->d1 = (double *)std::malloc(n * w * sizeof(double));
    out->d2 = (double *)std::malloc(n * w * sizeof(double));
    out->quads = (int *)std::malloc((size_t)out->quad_count * 4 * sizeof(int));
    if (!out->value || !out->d1 || !out->d2 || !out->quads) {
        plm_subdiv_limit_free(out);
        return plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory refining a %d-vertex cage", cage->vertex_count);
    }
    for (size_t i = 0; i < n; ++i) {
        std::memcpy(out->value + i * w, pos[i].v, sizeof(double) * (size_t)w);
        std::memcpy(out->d1 + i * w, d1[i].v, sizeof(double) * (size_t)w);
        std::memcpy(out->d2 + i * w, d2[i].v, sizeof(double) * (size_t)w);
    }
    for (int f = 0; f < out->quad_count; ++f) {
        Far::ConstIndexArray fv = last.GetFaceVertices(f);
        for (int k = 0; k < 4; ++k)
            out->quads[4 * f + k] = fv[k];
    }
    return PLM_OK;
}

extern "C" plm_result plm_subdiv_fit(const plm_subdiv_cage *cage, double *values, int iterations, double *residual,
                                     plm_error *err)
{
    return plm_guard(err, "subdivision fit", [&] { return subdiv_fit(cage, values, iterations, residual, err); });
}

extern "C" plm_result plm_subdiv_refine(const plm_subdiv_cage *cage, const double *values, int level,
                                        plm_subdiv_limit *out, plm_error *err)
{
    std::memset(out, 0, sizeof *out);
    return plm_guard(err, "subdivision", [&] { return subdiv_refine(cage, values, level, out, err); });
}

extern "C" void plm_subdiv_limit_free(plm_subdiv_limit *l)
{
    std::free(l->value);
    std::free(l->d1);
    std::free(l->d2);
    std::free(l->quads);
    std::memset(l, 0, sizeof *l);
}
