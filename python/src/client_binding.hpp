// _nclink.Core, the client binding (client_binding.cpp).
#pragma once

#include <pybind11/pybind11.h>

namespace nclink::python {

void bind_client(pybind11::module_& module);
/// _nclink.bench_cpp_query: the C++ client's Query round trip, for bench/.
void bind_bench_hooks(pybind11::module_& module);

}  // namespace nclink::python
