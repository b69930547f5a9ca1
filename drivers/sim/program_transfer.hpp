// The simulated mill's program_transfer method: copies a G-code file between
// the controller's program directory and a local path, the way a controller
// pulls a part program from a file server. Progress follows the bytes; a
// cancel midway leaves nothing behind (the copy goes to a temp file beside
// the destination, renamed into place only when complete).
#pragma once

#include <nclink/clock.hpp>
#include <nclink/driver.hpp>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

namespace nclink::sim {

struct TransferSettings {
    /// The controller's program directory ("" = transfers refused, 202).
    std::string program_dir;
    /// Simulated link speed in bytes per second of the injected clock (0 = as
    /// fast as the disk).
    std::uint64_t bytes_per_second = 0;
    std::size_t chunk_bytes = 1024;
    std::shared_ptr<const Clock> clock;
};

/// args (checked by the SDK against the model first):
///   operation   "push" (default): local `source` -> program directory;
///               "pull": program directory `source` -> local `destination`
///   source      a local path (push) or a program name (pull)
///   destination a program name (push; default: the source's file name) or a
///               local path (pull, required)
///   protocol    absent, "FILE" or "LOCAL" (the simulator copies local files)
/// A program name is a plain file name inside program_dir (no '/', '..').
/// Returns {"operation", "source", "destination", "bytes"}. Errors: 102 a
/// missing source/destination, 101 an unknown operation or protocol, 301 a
/// program name leaving the directory, 202 unreadable/unwritable files or no
/// program directory. Cancelled: removes the temp file, returns {"bytes": n}
/// (the bytes copied before the cancel). Thread: the method thread; touches
/// no simulator state, so reads go on meanwhile.
Result<Json> transfer_program(const TransferSettings& settings, const Json& args, MethodControl& control);

}  // namespace nclink::sim
