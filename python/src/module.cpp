// The extension module nclink._nclink. `import nclink` loads it; the public
// API is the Python package around it (python/nclink/__init__.py).
#include "client_binding.hpp"
#include "sample_batch.hpp"

#include <nclink/error.hpp>
#include <nclink/version.hpp>

#include <pybind11/pybind11.h>

namespace py = pybind11;

PYBIND11_MODULE(_nclink, m) {
    m.doc() = "nclink's C++ client (nclink::Client) for Python; use the nclink package";
    m.def(
        "reason", [](int code) { return std::string(nclink::reason(static_cast<nclink::ErrorCode>(code))); }, py::arg("code"),
        "The table-19 reason string of a code.");
    m.attr("sdk_version") = std::string(nclink::library_version());
    nclink::python::bind_sample_batch(m);
    nclink::python::bind_client(m);
    nclink::python::bind_bench_hooks(m);
}
