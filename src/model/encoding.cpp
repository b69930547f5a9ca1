// UTF-8 validation and GBK conversion. Deployed HNC model files are GBK; we
// convert once at load so everything in memory (and on the wire) is UTF-8.
#include "model/encoding.hpp"

#include <iconv.h>

#include <cerrno>
#include <cstdint>
#include <vector>

namespace nclink::model_detail {

bool is_valid_utf8(std::string_view text) noexcept {
    const auto* p = reinterpret_cast<const unsigned char*>(text.data());
    const std::size_t n = text.size();
    std::size_t i = 0;
    while (i < n) {
        const unsigned char c = p[i];
        if (c < 0x80) {
            ++i;
            continue;
        }
        std::size_t len = 0;
        std::uint32_t cp = 0;
        if ((c & 0xE0) == 0xC0) {
            len = 2;
            cp = c & 0x1F;
        } else if ((c & 0xF0) == 0xE0) {
            len = 3;
            cp = c & 0x0F;
        } else if ((c & 0xF8) == 0xF0) {
            len = 4;
            cp = c & 0x07;
        } else {
            return false;
        }
        if (i + len > n) return false;
        for (std::size_t k = 1; k < len; ++k) {
            if ((p[i + k] & 0xC0) != 0x80) return false;
            cp = (cp << 6) | (p[i + k] & 0x3F);
        }
        if ((len == 2 && cp < 0x80) || (len == 3 && cp < 0x800) || (len == 4 && cp < 0x10000)) return false;  // overlong
        if (cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) return false;
        i += len;
    }
    return true;
}

std::optional<std::string> gbk_to_utf8(std::string_view text) {
    iconv_t cd = iconv_open("UTF-8", "GBK");
    if (cd == reinterpret_cast<iconv_t>(-1)) return std::nullopt;
    std::string out;
    // Every GBK character (1 or 2 bytes) becomes at most 3 UTF-8 bytes.
    std::vector<char> buffer(text.size() * 2 + 16);
    std::vector<char> input(text.begin(), text.end());
    char* in = input.data();
    std::size_t in_left = input.size();
    bool ok = true;
    while (in_left > 0) {
        char* outp = buffer.data();
        std::size_t out_left = buffer.size();
        const std::size_t r = iconv(cd, &in, &in_left, &outp, &out_left);
        out.append(buffer.data(), buffer.size() - out_left);
        if (r == static_cast<std::size_t>(-1) && errno != E2BIG) {
            ok = false;  // EILSEQ or EINVAL (truncated sequence)
            break;
        }
    }
    iconv_close(cd);
    if (!ok) return std::nullopt;
    return out;
}

}  // namespace nclink::model_detail
