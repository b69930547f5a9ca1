#include "sampling/spool_segment.hpp"

#include "core/atomic_file.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>

namespace nclink::sampling_detail {
namespace {

constexpr char kMagic[] = "NCLSPL1\n";
constexpr std::size_t kMagicSize = 8;
constexpr std::size_t kRecordHeader = 12;  // u32 topic_len, u32 payload_len, u8 qos, u8 flags, u16 0
constexpr std::size_t kRecordTrailer = 4;  // u32 crc

std::array<std::uint32_t, 256> make_crc_table() {
    std::array<std::uint32_t, 256> table{};
    for (std::uint32_t i = 0; i < 256; ++i) {
        std::uint32_t c = i;
        for (int k = 0; k < 8; ++k) c = (c & 1u) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
        table[i] = c;
    }
    return table;
}

void put_u32(std::string& out, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xFFu));
}

std::uint32_t get_u32(const std::string& in, std::size_t at) {
    std::uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v |= static_cast<std::uint32_t>(static_cast<unsigned char>(in[at + i])) << (8 * i);
    return v;
}

bool parse_name(const std::string& name, std::uint64_t& seq, std::size_t& records) {
    // "<16 hex>-<decimal>.seg"
    if (name.size() < 16 + 1 + 1 + 4 || name.compare(name.size() - 4, 4, ".seg") != 0 || name[16] != '-') return false;
    seq = 0;
    for (std::size_t i = 0; i < 16; ++i) {
        const char c = name[i];
        int d = 0;
        if (c >= '0' && c <= '9') d = c - '0';
        else if (c >= 'a' && c <= 'f') d = c - 'a' + 10;
        else return false;
        seq = (seq << 4) | static_cast<std::uint64_t>(d);
    }
    records = 0;
    for (std::size_t i = 17; i + 4 < name.size(); ++i) {
        if (name[i] < '0' || name[i] > '9') return false;
        records = records * 10 + static_cast<std::size_t>(name[i] - '0');
    }
    return true;
}

}  // namespace

std::uint32_t crc32(const void* data, std::size_t size, std::uint32_t crc) noexcept {
    static const auto table = make_crc_table();
    const auto* p = static_cast<const unsigned char*>(data);
    crc = ~crc;
    for (std::size_t i = 0; i < size; ++i) crc = table[(crc ^ p[i]) & 0xFFu] ^ (crc >> 8);
    return ~crc;
}

std::size_t segment_record_size(const Message& m) noexcept {
    return kRecordHeader + m.topic.size() + m.payload.size() + kRecordTrailer;
}

std::string encode_segment(const std::vector<Message>& messages) {
    std::size_t total = kMagicSize;
    for (const auto& m : messages) total += segment_record_size(m);
    std::string out;
    out.reserve(total);
    out.append(kMagic, kMagicSize);
    for (const auto& m : messages) {
        const std::size_t start = out.size();
        put_u32(out, static_cast<std::uint32_t>(m.topic.size()));
        put_u32(out, static_cast<std::uint32_t>(m.payload.size()));
        out.push_back(static_cast<char>(m.qos & 0xFF));
        out.push_back(static_cast<char>(m.retained ? 1 : 0));
        out.push_back('\0');
        out.push_back('\0');
        out += m.topic;
        out += m.payload;
        put_u32(out, crc32(out.data() + start, out.size() - start));
    }
    return out;
}

SegmentContents decode_segment(const std::string& bytes, std::size_t expected) {
    SegmentContents contents;
    std::size_t at = kMagicSize;
    if (bytes.size() >= kMagicSize && bytes.compare(0, kMagicSize, kMagic, kMagicSize) == 0) {
        while (at + kRecordHeader + kRecordTrailer <= bytes.size()) {
            const std::size_t topic_len = get_u32(bytes, at);
            const std::size_t payload_len = get_u32(bytes, at + 4);
            const std::size_t body = kRecordHeader + topic_len + payload_len;
            if (topic_len > bytes.size() || payload_len > bytes.size() || at + body + kRecordTrailer > bytes.size()) break;
            if (crc32(bytes.data() + at, body) != get_u32(bytes, at + body)) break;
            Message m;
            m.qos = static_cast<unsigned char>(bytes[at + 8]);
            m.retained = (static_cast<unsigned char>(bytes[at + 9]) & 1u) != 0;
            m.topic.assign(bytes, at + kRecordHeader, topic_len);
            m.payload.assign(bytes, at + kRecordHeader + topic_len, payload_len);
            contents.messages.push_back(std::move(m));
            at += body + kRecordTrailer;
        }
    }
    contents.damaged = expected > contents.messages.size() ? expected - contents.messages.size() : 0;
    return contents;
}

Result<SegmentInfo> write_segment(const std::string& dir, std::uint64_t seq, const std::vector<Message>& messages) {
    SegmentInfo info;
    info.seq = seq;
    info.records = messages.size();
    info.path = (std::filesystem::path(dir) / fmt::format("{:016x}-{}.seg", seq, messages.size())).string();
    const std::string bytes = encode_segment(messages);
    info.bytes = bytes.size();
    if (auto written = core_detail::write_file_atomically(info.path, bytes); !written) return std::move(written).error();
    return info;
}

SegmentContents read_segment(const SegmentInfo& segment) {
    std::ifstream in(segment.path, std::ios::binary);
    if (!in) {
        SegmentContents none;
        none.damaged = segment.records;
        return none;
    }
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    return decode_segment(bytes, segment.records);
}

Result<std::vector<SegmentInfo>> list_segments(const std::string& dir) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec) return make_error(ErrorCode::unavailable, fmt::format("cannot create {}: {}", dir, ec.message()));
    std::vector<SegmentInfo> out;
    for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
        const std::string name = entry.path().filename().string();
        if (name.size() > 4 && name.compare(name.size() - 4, 4, ".tmp") == 0) {
            std::filesystem::remove(entry.path(), ec);  // a crash while writing: never complete
            continue;
        }
        SegmentInfo info;
        if (!entry.is_regular_file(ec) || !parse_name(name, info.seq, info.records)) continue;
        info.path = entry.path().string();
        info.bytes = static_cast<std::size_t>(entry.file_size(ec));
        out.push_back(std::move(info));
    }
    if (ec) return make_error(ErrorCode::unavailable, fmt::format("cannot list {}: {}", dir, ec.message()));
    std::sort(out.begin(), out.end(), [](const SegmentInfo& a, const SegmentInfo& b) { return a.seq < b.seq; });
    return out;
}

}  // namespace nclink::sampling_detail
