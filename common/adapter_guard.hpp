// The C entry points of the C++ adapters (image_io.cpp, mesh_io.cpp,
// generate/subdiv.cpp) let no exception cross into C: plm_guard runs the body
// and turns whatever it throws into a plm_result with a message naming what
// was being done. C++ only; include it after the C headers.
#ifndef PLUMAGE_COMMON_ADAPTER_GUARD_HPP
#define PLUMAGE_COMMON_ADAPTER_GUARD_HPP

#include <exception>
#include <new>

extern "C" {
#include "common/error.h"
}

template <class Body>
plm_result plm_guard(plm_error *err, const char *what, Body &&body) noexcept
{
    try {
        return body();
    } catch (const std::bad_alloc &) {
        return plm_fail(err, PLM_ERR_NO_MEMORY, "%s: out of memory", what);
    } catch (const std::exception &e) {
        return plm_fail(err, PLM_ERR_INTERNAL, "%s: %s", what, e.what());
    } catch (...) {
        return plm_fail(err, PLM_ERR_INTERNAL, "%s: unexpected failure in a C++ library", what);
    }
}

#endif
