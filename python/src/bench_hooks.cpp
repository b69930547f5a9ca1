// For bench/bench_python.py: the Query round trip of the C++ client, measured
// in the same process and run as the Python one, so the two figures share
// the broker, the adapter and the machine's load at that moment.
#include "client_binding.hpp"

#include "errors.hpp"

#include <nclink/client.hpp>
#include <nclink/mqtt_transport.hpp>

#include <pybind11/stl.h>

#include <chrono>

namespace nclink::python {

namespace py = pybind11;

void bind_bench_hooks(py::module_& m) {
    m.def(
        "bench_cpp_query",
        [](const std::string& broker, const std::string& client_id, const std::string& dev, const std::string& item, int count) {
            MqttOptions mqtt;
            mqtt.broker_url = broker;
            ClientOptions options;
            options.ex_cid = client_id;
            std::vector<double> micros;
            std::optional<Error> failed;
            {
                py::gil_scoped_release nogil;
                auto created = Client::create(mqtt, options);
                if (!created) {
                    failed = created.error();
                } else {
                    auto client = std::move(created).value();
                    if (auto started = client->start(); !started) failed = started.error();
                    else if (!client->wait_connected(std::chrono::seconds(5)))
                        failed = make_error(ErrorCode::timeout, "no broker connection");
                    for (int i = 0; !failed && i < count; ++i) {
                        const auto t0 = std::chrono::steady_clock::now();
                        auto r = client->query(dev, {QueryItem{item, std::nullopt}});
                        const auto t1 = std::chrono::steady_clock::now();
                        if (!r) failed = r.error();
                        else micros.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count());
                    }
                    client->stop();
                }
            }
            if (failed) raise_error(*failed);
            return micros;
        },
        py::arg("broker"), py::arg("client_id"), py::arg("dev"), py::arg("item"), py::arg("count"),
        "Query round trips of nclink::Client (microseconds each), for the benchmark.");
}

}  // namespace nclink::python
