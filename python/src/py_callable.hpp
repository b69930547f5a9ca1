// A Python callable that C++ threads hold and call: the client's dispatch
// thread runs every callback (docs/python.md, "Threads"). Copies share one
// reference, so copying needs no GIL; the last copy drops the reference with
// the GIL held (or leaves it when the interpreter is already shutting down,
// when taking the GIL would hang the thread).
#pragma once

#include <pybind11/pybind11.h>

#include <memory>
#include <utility>

namespace nclink::python {

namespace py = pybind11;

/// Set while a callback of a client runs on its dispatch thread: a blocking
/// call of that client from there would wait for its own thread.
inline thread_local const void* dispatching_client = nullptr;

/// True while Python can run code (not finalizing).
inline bool python_alive() noexcept { return Py_IsInitialized() != 0 && _Py_IsFinalizing() == 0; }

class PyCallable {
public:
    PyCallable() = default;
    /// Needs the GIL. None gives an empty callable.
    explicit PyCallable(const py::object& fn) {
        if (!fn.is_none()) fn_.reset(new py::object(fn), Release{});
    }

    bool empty() const noexcept { return !fn_; }

    /// Calls fn(make_args()...) on this thread with the GIL taken. make
    /// builds the arguments under the GIL (a py::tuple). An exception the
    /// callback raises goes to sys.unraisablehook (printed by default): it
    /// never reaches the client, whose other callbacks go on.
    template <class MakeArgs>
    void call(const void* client, MakeArgs&& make) const {
        if (!fn_ || !python_alive()) return;
        py::gil_scoped_acquire gil;
        const void* outer = dispatching_client;
        dispatching_client = client;
        try {
            py::tuple args = make();
            (*fn_)(*args);
        } catch (py::error_already_set& error) {
            error.discard_as_unraisable(*fn_);
        } catch (const std::exception& error) {
            PyErr_SetString(PyExc_RuntimeError, error.what());
            PyErr_WriteUnraisable(fn_->ptr());
        }
        dispatching_client = outer;
    }

private:
    struct Release {
        void operator()(py::object* fn) const {
            if (!python_alive()) {
                (void)fn->release();  // the interpreter is going away: leave the reference
                delete fn;
                return;
            }
            py::gil_scoped_acquire gil;
            delete fn;
        }
    };
    std::shared_ptr<py::object> fn_;
};

}  // namespace nclink::python
