#include "program_transfer.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>
#include <vector>

namespace nclink::sim {
namespace fs = std::filesystem;

namespace {

std::string string_arg(const Json& args, const char* key) {
    auto it = args.find(key);
    return it != args.end() && it->is_string() ? it->get<std::string>() : std::string();
}

bool plain_file_name(const std::string& name) {
    return !name.empty() && name != "." && name != ".." && name.find('/') == std::string::npos &&
           name.find('\\') == std::string::npos && name.find('\0') == std::string::npos;
}

/// A name for the partial copy next to `target`, unique per transfer.
fs::path temp_beside(const fs::path& target) {
    static std::atomic<std::uint64_t> counter{0};
    return target.parent_path() / ("." + target.filename().string() + ".nclink-part-" + std::to_string(++counter));
}

/// Waits (polling the injected clock, which tests move by hand) until `bytes`
/// may have crossed the simulated link. False when cancelled meanwhile.
bool pace(const TransferSettings& settings, Clock::Steady begin, std::uint64_t bytes, MethodControl& control) {
    if (settings.bytes_per_second == 0) return !control.cancelled();
    const auto due = begin + std::chrono::duration_cast<Clock::Steady::duration>(std::chrono::duration<double>(
                                 static_cast<double>(bytes) / static_cast<double>(settings.bytes_per_second)));
    while (settings.clock->now() < due) {
        if (control.cancelled()) return false;
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return !control.cancelled();
}

}  // namespace

Result<Json> transfer_program(const TransferSettings& settings, const Json& args, MethodControl& control) {
    const std::string operation = args.contains("operation") ? string_arg(args, "operation") : "push";
    if (operation != "push" && operation != "pull")
        return make_error(ErrorCode::out_of_range, "operation must be push or pull, not \"" + operation + "\"");
    const std::string protocol = string_arg(args, "protocol");
    if (!protocol.empty() && protocol != "FILE" && protocol != "file" && protocol != "LOCAL" && protocol != "local")
        return make_error(ErrorCode::out_of_range, "the simulator copies local files only (protocol FILE), not " + protocol);
    if (settings.program_dir.empty())
        return make_error(ErrorCode::unavailable, "no program directory configured (driver configuration key program_dir)");
    const std::string source = string_arg(args, "source");
    std::string destination = string_arg(args, "destination");
    if (source.empty()) return make_error(ErrorCode::parameter_missing, "program_transfer needs a source");
    fs::path from, to;
    if (operation == "push") {
        if (destination.empty()) destination = fs::path(source).filename().string();
        if (!plain_file_name(destination))
            return make_error(ErrorCode::permission_denied, "program name \"" + destination + "\" leaves the program directory");
        from = source;
        to = fs::path(settings.program_dir) / destination;
    } else {
        if (destination.empty()) return make_error(ErrorCode::parameter_missing, "pull needs a destination path");
        if (!plain_file_name(source))
            return make_error(ErrorCode::permission_denied, "program name \"" + source + "\" leaves the program directory");
        from = fs::path(settings.program_dir) / source;
        to = destination;
    }

    std::error_code ec;
    const auto size = fs::file_size(from, ec);
    if (ec || !fs::is_regular_file(from, ec)) return make_error(ErrorCode::unavailable, "cannot read " + from.string());
    std::ifstream in(from, std::ios::binary);
    if (!in) return make_error(ErrorCode::unavailable, "cannot open " + from.string());
    if (to.has_parent_path()) fs::create_directories(to.parent_path(), ec);
    const fs::path part = temp_beside(to);
    std::ofstream out(part, std::ios::binary | std::ios::trunc);
    if (!out) return make_error(ErrorCode::unavailable, "cannot write " + part.string());

    auto abandon = [&] {
        out.close();
        std::error_code ignored;
        fs::remove(part, ignored);
    };
    const auto begin = settings.clock->now();
    std::vector<char> buffer(std::max<std::size_t>(1, settings.chunk_bytes));
    std::uint64_t copied = 0;
    control.progress(size == 0 ? 100 : 0);
    while (copied < size) {
        if (!control.checkpoint()) {  // paused here until resumed; false = cancelled
            abandon();
            return Json{{"bytes", copied}};
        }
        const auto want = static_cast<std::streamsize>(std::min<std::uint64_t>(buffer.size(), size - copied));
        in.read(buffer.data(), want);
        const auto got = in.gcount();
        if (got <= 0) break;  // the file shrank meanwhile: copy what there is
        out.write(buffer.data(), got);
        if (!out) {
            abandon();
            return make_error(ErrorCode::unavailable, "writing " + part.string() + " failed");
        }
        copied += static_cast<std::uint64_t>(got);
        if (!pace(settings, begin, copied, control)) {
            abandon();
            return Json{{"bytes", copied}};
        }
        control.progress(100.0 * static_cast<double>(copied) / static_cast<double>(size));
    }
    out.close();
    if (!out || control.cancelled()) {
        fs::remove(part, ec);
        if (control.cancelled()) return Json{{"bytes", copied}};
        return make_error(ErrorCode::unavailable, "writing " + part.string() + " failed");
    }
    fs::rename(part, to, ec);  // atomic on one file system: never a partial program
    if (ec) {
        fs::remove(part, ec);
        return make_error(ErrorCode::unavailable, "cannot move the copy into " + to.string());
    }
    control.progress(100);
    return Json{{"operation", operation}, {"source", source}, {"destination", destination}, {"bytes", copied}};
}

}  // namespace nclink::sim
