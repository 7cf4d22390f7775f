// A NumPy .npz archive, written member by member into a byte sink (internal to imuconv_pipeline).
//
// What numpy.load reads: a ZIP archive whose members are "NAME.npy" files in the .npy format 1.0
// (magic "\x93NUMPY", version 1.0, a little-endian uint16 header length, a Python dict literal
// padded with spaces to a multiple of 64 bytes and ended by '\n', then the data in C order).
// Members are "stored" (method 0, no compression), so that a member's bytes are the array's
// bytes. Every time stamp is 1980-01-01 00:00 (the first DOS date): the same arrays give the
// same archive, byte for byte.
//
// ZIP64: the classic records hold 32-bit sizes and offsets and a 16-bit member count. When a
// member's size or its local header's offset reaches 0xFFFFFFFF, the member carries the ZIP64
// extra field (0x0001) with the 64-bit values; when the member count reaches 0xFFFF or the
// central directory's size or offset reaches 0xFFFFFFFF, the ZIP64 end-of-central-directory
// record and its locator precede the classic end record, whose fields then read 0xFFFF /
// 0xFFFFFFFF (APPNOTE 6.3, sections 4.3.14-4.3.16, 4.5.3). Python's zipfile, which numpy.load
// uses, reads both forms. force_zip64 writes the ZIP64 form for every member and the end (for
// tests: a 4 GiB archive is too large for the test suite).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace imuconv::pipeline {

/// CRC-32 as ZIP uses it (polynomial 0xEDB88320 reflected, initial and final complement),
/// continued from `crc` (0 to start).
std::uint32_t Crc32(std::uint32_t crc, const void* data, std::size_t size);

/// The .npy (format 1.0) header for an array of dtype `descr` ("<f8", "<i8", "<U12") and
/// `shape` (empty: a 0-d array), C order. Its length is a multiple of 64.
std::string NpyHeader(const std::string& descr, const std::vector<std::size_t>& shape);

class NpzWriter {
 public:
  using Sink = std::function<void(std::string_view)>;
  explicit NpzWriter(Sink sink, bool force_zip64 = false)
      : sink_(std::move(sink)), force_zip64_(force_zip64) {}

  /// Writes member `name` + ".npy": the header for `descr` and `shape`, then `data`, the
  /// array's bytes (little-endian, C order; their count must be the shape's size times the
  /// item size, which the caller guarantees). Names must be unique (the caller's rule).
  void add(const std::string& name, const std::string& descr, const std::vector<std::size_t>& shape,
           std::string_view data);
  /// Writes the central directory and the end records. Nothing may be added afterwards.
  void finish();
  /// Bytes written so far.
  std::uint64_t written() const noexcept { return offset_; }

 private:
  struct Member {
    std::string name;
    std::uint32_t crc;
    std::uint64_t size;
    std::uint64_t offset;
  };
  void emit(std::string_view bytes);

  Sink sink_;
  bool force_zip64_;
  bool finished_ = false;
  std::uint64_t offset_ = 0;
  std::vector<Member> members_;
};

}  // namespace imuconv::pipeline
