#include "core/atomic_file.hpp"

#include <fmt/format.h>
#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

namespace nclink::core_detail {

namespace {
Error io_error(const char* what, const std::string& path, int err) {
    return make_error(ErrorCode::unavailable, fmt::format("cannot {} {}: {}", what, path, std::strerror(err)));
}
}  // namespace

Result<void> write_file_atomically(const std::string& path, const std::string& text) {
    std::error_code ec;
    const auto parent = std::filesystem::path(path).parent_path();
    if (!parent.empty()) std::filesystem::create_directories(parent, ec);
    const std::string temp = path + ".tmp";
    const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) return io_error("write", temp, errno);
    std::size_t written = 0;
    while (written < text.size()) {
        const ssize_t n = ::write(fd, text.data() + written, text.size() - written);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            const int err = n < 0 ? errno : ENOSPC;
            ::close(fd);
            std::remove(temp.c_str());
            return io_error("write", temp, err);
        }
        written += static_cast<std::size_t>(n);
    }
    const bool synced = ::fsync(fd) == 0;
    const int sync_err = errno;
    ::close(fd);
    if (!synced) {
        std::remove(temp.c_str());
        return io_error("sync", temp, sync_err);
    }
    if (std::rename(temp.c_str(), path.c_str()) != 0) {
        const int err = errno;
        std::remove(temp.c_str());
        return io_error("replace", path, err);
    }
    return ok_result();
}

}  // namespace nclink::core_detail
