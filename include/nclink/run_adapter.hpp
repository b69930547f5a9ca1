// The standard adapter program in one call: what every adapter main()
// otherwise repeats (command line, configuration file, logger, signals,
// start, wait, stop, exit status).
//
//   int main(int argc, char** argv) {
//       auto driver = std::make_shared<AcmeLatheDriver>();
//       return nclink::run_adapter(argc, argv, driver);
//   }
//
// Command line (docs/configuration.md has the file's keys):
//   PROGRAM [--config FILE] [--broker URL] [--model FILE] [--log-level LEVEL]
//           [--check] [--help] [--version]
// Without --config, `adapter.json` in the current directory is read if it
// exists. Options given on the command line win over the file.
//
// Exit status: 0 after SIGINT/SIGTERM (a clean stop); 1 when the adapter
// cannot start (the reason is logged: unreadable model, driver open()
// failure...); 2 for usage and configuration errors (printed to stderr with
// the usage). --check loads configuration and model, prints what would run
// and exits 0 (or 1/2) without opening the driver or connecting.
//
// Threading: call it from main(), once, before any other thread of the
// process starts: it blocks SIGINT and SIGTERM in the calling thread (the
// threads the SDK starts inherit that) and waits for them with sigwait().
#pragma once

#include <nclink/adapter_config.hpp>
#include <nclink/driver.hpp>
#include <nclink/export.hpp>

#include <functional>
#include <memory>
#include <string>

namespace nclink {

class Adapter;

struct NCLINK_API RunAdapterOptions {
    /// Shown in messages and the usage text; default: argv[0]'s file name.
    std::string program;
    /// Read when --config is not given and the file exists ("" = none).
    std::string default_config = "adapter.json";
    /// The base the configuration file and options are applied to: set
    /// defaults of the program here (e.g. model_path).
    AdapterConfig defaults;
    /// Called after a successful start, on the calling thread (e.g. to start
    /// the firmware's own loop that feeds PointValues or push channels).
    std::function<void(Adapter&)> on_started;
};

/// Runs an adapter with `driver` (nullptr: the configuration's driver.plugin)
/// until SIGINT/SIGTERM. Returns the process exit status (see above).
NCLINK_API int run_adapter(int argc, char** argv, std::shared_ptr<Driver> driver, RunAdapterOptions options = {});

}  // namespace nclink
