// nclink-lathe: the ACME 2-axis lathe on NC-Link. Everything a vendor writes
// is lathe.json (the model), lathe_driver.hpp (the points) and this file.
//
//   nclink-lathe [--config FILE] [--broker URL] [--model FILE] [--log-level LEVEL]
#include "lathe_driver.hpp"

#include <nclink/run_adapter.hpp>

int main(int argc, char** argv) {
    acme::LatheMachine cnc;
    nclink::RunAdapterOptions options;
    options.defaults.model_path = NCLINK_LATHE_MODEL;  // the model next to this file
    options.on_started = [&cnc](nclink::Adapter&) { cnc.start(); };
    return nclink::run_adapter(argc, argv, acme::make_lathe_driver(cnc), options);
}
