// Files that are either complete or absent: the persisted model and values,
// spool segments and the agent's state are written through here, so a crash
// or power loss mid-write never leaves a half-written file behind.
#pragma once

#include <nclink/result.hpp>

#include <string>

namespace nclink::core_detail {

/// Writes `text` to `path` atomically: a sibling temp file, fsync, rename.
/// Creates missing parent directories. The error names the file and errno.
Result<void> write_file_atomically(const std::string& path, const std::string& text);

}  // namespace nclink::core_detail
