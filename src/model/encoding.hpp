// Text encoding of model files: UTF-8, or GBK as deployed HNC files are.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace nclink::model_detail {

/// Strict UTF-8 check (no overlong forms, no surrogates, nothing above U+10FFFF).
bool is_valid_utf8(std::string_view text) noexcept;

/// GBK -> UTF-8 with glibc iconv; std::nullopt when the bytes are not GBK
/// either (or the converter is unavailable).
std::optional<std::string> gbk_to_utf8(std::string_view text);

}  // namespace nclink::model_detail
