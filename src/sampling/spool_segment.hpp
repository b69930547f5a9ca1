// Disk segments of the sample spool (see sample_spool.hpp): a batch of
// spooled Sample DTUs in one file, written so that a crash never leaves a
// half-written segment behind.
//
// A segment is written whole to "<name>.tmp", fsync'ed and renamed into place
// (write_file_atomically), so a segment file either exists complete or not at
// all; leftover *.tmp files are garbage from a crash and are removed on start.
// Every record also carries a CRC-32, so a file damaged later (bad flash, a
// copy cut short) is read up to its first bad record and the rest counted as
// lost instead of replaying garbage.
//
// File name: "<seq as 16 hex digits>-<records>.seg"; seq grows, so names sort
// oldest first. Layout (little-endian):
//   "NCLSPL1\n"
//   per record: u32 topic_len, u32 payload_len, u8 qos, u8 flags, u16 0,
//               topic, payload, u32 crc32(all of the record before it)
#pragma once

#include <nclink/result.hpp>
#include <nclink/transport.hpp>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace nclink::sampling_detail {

struct SegmentInfo {
    std::string path;
    std::uint64_t seq = 0;
    std::size_t records = 0;  ///< from the file name
    std::size_t bytes = 0;    ///< file size
};

struct SegmentContents {
    std::vector<Message> messages;
    std::size_t damaged = 0;  ///< records announced by the name but unreadable
};

/// Bytes a record of `m` takes in a segment file.
std::size_t segment_record_size(const Message& m) noexcept;

/// Encodes `messages` as a segment file's bytes.
std::string encode_segment(const std::vector<Message>& messages);
/// Decodes a segment file's bytes up to the first damaged record.
/// `expected` is the record count the name announces (for `damaged`).
SegmentContents decode_segment(const std::string& bytes, std::size_t expected);

/// Writes a segment atomically into `dir`; returns its info.
Result<SegmentInfo> write_segment(const std::string& dir, std::uint64_t seq, const std::vector<Message>& messages);
/// Reads a whole segment (damaged records counted, never thrown).
SegmentContents read_segment(const SegmentInfo& segment);
/// The segments in `dir`, oldest first. Creates `dir`; removes leftover
/// *.tmp files (a crash while writing); ignores other files.
Result<std::vector<SegmentInfo>> list_segments(const std::string& dir);

/// CRC-32 (IEEE 802.3, as zlib's crc32), continuing from `crc`.
std::uint32_t crc32(const void* data, std::size_t size, std::uint32_t crc = 0) noexcept;

}  // namespace nclink::sampling_detail
