// The .npz writer: ZIP records as APPNOTE 6.3 lays them out (section numbers below), .npy 1.0
// headers as NumPy's format documentation (numpy.lib.format) describes them.
#include "npz_writer.h"

#include <array>

#include "imuconv/registry.h"

namespace imuconv::pipeline {
namespace {

constexpr std::uint32_t kMax32 = 0xFFFFFFFFu;
constexpr std::uint16_t kMax16 = 0xFFFFu;
// DOS date of 1980-01-01 (day 1, month 1, year 0 from 1980), time 00:00:00 (4.4.6).
constexpr std::uint16_t kDosDate = (1u << 5) | 1u, kDosTime = 0;
// "version needed to extract" (4.4.3.2): 2.0 for stored members, 4.5 for ZIP64 records.
constexpr std::uint16_t kVersionStored = 20, kVersionZip64 = 45;

void Put16(std::string& s, std::uint16_t v) {
  for (int i = 0; i < 2; ++i) s += static_cast<char>((v >> (8 * i)) & 0xFF);
}
void Put32(std::string& s, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) s += static_cast<char>((v >> (8 * i)) & 0xFF);
}
void Put64(std::string& s, std::uint64_t v) {
  for (int i = 0; i < 8; ++i) s += static_cast<char>((v >> (8 * i)) & 0xFF);
}

std::uint32_t Clamp32(std::uint64_t v) {
  return v >= kMax32 ? kMax32 : static_cast<std::uint32_t>(v);
}

/// General-purpose flag bit 11 (4.4.4): the name is UTF-8. Set only when it is not plain ASCII,
/// as zipfile and Info-ZIP do.
std::uint16_t NameFlags(const std::string& name) {
  for (unsigned char c : name)
    if (c >= 0x80) return 1u << 11;
  return 0;
}

// Slicing-by-8 (Kounavis and Berry, "A systematic approach to building high performance,
// software-based, CRC generators", 2005): table k holds the CRC of a byte followed by k zero
// bytes, so eight input bytes are folded into the register with eight independent lookups
// instead of eight dependent ones. Table 0 is the classic byte-wise table. The arithmetic is the
// byte-wise algorithm's, regrouped: the result is the same CRC for any split of the input.
using CrcTables = std::array<std::array<std::uint32_t, 256>, 8>;

const CrcTables& CrcTable() {
  static const CrcTables tables = [] {
    CrcTables t{};
    for (std::uint32_t n = 0; n < 256; ++n) {
      std::uint32_t c = n;
      for (int k = 0; k < 8; ++k) c = (c & 1u) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      t[0][n] = c;
    }
    for (std::size_t k = 1; k < 8; ++k)
      for (std::size_t n = 0; n < 256; ++n)
        t[k][n] = t[0][t[k - 1][n] & 0xFFu] ^ (t[k - 1][n] >> 8);
    return t;
  }();
  return tables;
}

}  // namespace

std::uint32_t Crc32(std::uint32_t crc, const void* data, std::size_t size) {
  const CrcTables& t = CrcTable();
  const auto* p = static_cast<const unsigned char*>(data);
  crc = ~crc;
  // Eight bytes at a time; the bytes are assembled little-endian by hand, so the result does not
  // depend on the machine's byte order.
  for (; size >= 8; size -= 8, p += 8) {
    const std::uint32_t lo = crc ^ (std::uint32_t{p[0]} | std::uint32_t{p[1]} << 8 |
                                    std::uint32_t{p[2]} << 16 | std::uint32_t{p[3]} << 24);
    crc = t[7][lo & 0xFFu] ^ t[6][(lo >> 8) & 0xFFu] ^ t[5][(lo >> 16) & 0xFFu] ^ t[4][lo >> 24] ^
          t[3][p[4]] ^ t[2][p[5]] ^ t[1][p[6]] ^ t[0][p[7]];
  }
  for (; size > 0; --size, ++p) crc = t[0][(crc ^ *p) & 0xFFu] ^ (crc >> 8);
  return ~crc;
}

std::string NpyHeader(const std::string& descr, const std::vector<std::size_t>& shape) {
  std::string tuple = "(";
  for (std::size_t i = 0; i < shape.size(); ++i)
    tuple += (i ? ", " : "") + std::to_string(shape[i]);
  if (shape.size() == 1) tuple += ",";
  tuple += ")";
  std::string dict = "{'descr': '" + descr + "', 'fortran_order': False, 'shape': " + tuple + ", }";
  // magic (6) + version (2) + header length (2) + dict + padding + '\n': a multiple of 64, so
  // that the data starts aligned (NumPy pads to 64 since 1.14; the format asks for 16).
  const std::size_t unpadded = 10 + dict.size() + 1;
  dict.append((64 - unpadded % 64) % 64, ' ');
  dict += '\n';
  if (dict.size() > kMax16)
    throw Error("npz: the .npy header of an array of " + std::to_string(shape.size()) +
                " dimensions is longer than format 1.0 allows");
  std::string h("\x93NUMPY\x01\x00", 8);
  Put16(h, static_cast<std::uint16_t>(dict.size()));
  return h + dict;
}

void NpzWriter::emit(std::string_view bytes) {
  sink_(bytes);
  offset_ += bytes.size();
}

void NpzWriter::add(const std::string& name, const std::string& descr,
                    const std::vector<std::size_t>& shape, std::string_view data) {
  if (finished_) throw Error("npz: member '" + name + "' added after the archive was finished");
  const std::string file = name + ".npy";
  if (file.size() > kMax16)
    throw Error("npz: a member name of " + std::to_string(file.size()) + " bytes is too long");
  const std::string header = NpyHeader(descr, shape);
  const std::uint64_t size = header.size() + data.size();
  const std::uint32_t crc = Crc32(Crc32(0, header.data(), header.size()), data.data(), data.size());
  const bool zip64 = force_zip64_ || size >= kMax32;
  // Local file header (4.3.7); with ZIP64, both sizes move to the extra field (4.5.3).
  std::string local;
  Put32(local, 0x04034b50u);
  Put16(local, zip64 ? kVersionZip64 : kVersionStored);
  Put16(local, NameFlags(file));
  Put16(local, 0);  // method: stored
  Put16(local, kDosTime);
  Put16(local, kDosDate);
  Put32(local, crc);
  Put32(local, zip64 ? kMax32 : static_cast<std::uint32_t>(size));  // compressed size
  Put32(local, zip64 ? kMax32 : static_cast<std::uint32_t>(size));  // uncompressed size
  Put16(local, static_cast<std::uint16_t>(file.size()));
  Put16(local, zip64 ? 20 : 0);
  local += file;
  if (zip64) {
    Put16(local, 0x0001);
    Put16(local, 16);
    Put64(local, size);  // original size first, then compressed size (4.5.3)
    Put64(local, size);
  }
  members_.push_back({file, crc, size, offset_});
  emit(local);
  emit(header);
  emit(data);
}

void NpzWriter::finish() {
  if (finished_) return;
  finished_ = true;
  const std::uint64_t cd_offset = offset_;
  std::string cd;
  for (const Member& m : members_) {
    const bool big_size = force_zip64_ || m.size >= kMax32,
               big_offset = force_zip64_ || m.offset >= kMax32;
    // The ZIP64 extra field holds, in this order, only the values whose classic field reads
    // 0xFFFFFFFF: uncompressed size, compressed size, local header offset (4.5.3).
    std::string extra;
    if (big_size || big_offset) {
      Put16(extra, 0x0001);
      Put16(extra, static_cast<std::uint16_t>((big_size ? 16 : 0) + (big_offset ? 8 : 0)));
      if (big_size) {
        Put64(extra, m.size);
        Put64(extra, m.size);
      }
      if (big_offset) Put64(extra, m.offset);
    }
    // Central directory file header (4.3.12).
    Put32(cd, 0x02014b50u);
    Put16(cd, kVersionZip64);  // version made by: 4.5, MS-DOS attributes (none set)
    Put16(cd, extra.empty() ? kVersionStored : kVersionZip64);
    Put16(cd, NameFlags(m.name));
    Put16(cd, 0);
    Put16(cd, kDosTime);
    Put16(cd, kDosDate);
    Put32(cd, m.crc);
    Put32(cd, big_size ? kMax32 : static_cast<std::uint32_t>(m.size));
    Put32(cd, big_size ? kMax32 : static_cast<std::uint32_t>(m.size));
    Put16(cd, static_cast<std::uint16_t>(m.name.size()));
    Put16(cd, static_cast<std::uint16_t>(extra.size()));
    Put16(cd, 0);  // comment length
    Put16(cd, 0);  // disk number start
    Put16(cd, 0);  // internal attributes
    Put32(cd, 0);  // external attributes
    Put32(cd, big_offset ? kMax32 : static_cast<std::uint32_t>(m.offset));
    cd += m.name;
    cd += extra;
  }
  const std::uint64_t count = members_.size(), cd_size = cd.size();
  emit(cd);
  const std::uint64_t end64_offset = offset_;
  const bool zip64_end =
      force_zip64_ || count >= kMax16 || cd_size >= kMax32 || cd_offset >= kMax32;
  std::string end;
  if (zip64_end) {
    // ZIP64 end of central directory record (4.3.14) and its locator (4.3.15).
    Put32(end, 0x06064b50u);
    Put64(end, 44);  // the record's size, not counting these first 12 bytes
    Put16(end, kVersionZip64);
    Put16(end, kVersionZip64);
    Put32(end, 0);  // this disk
    Put32(end, 0);  // the disk where the central directory starts
    Put64(end, count);
    Put64(end, count);
    Put64(end, cd_size);
    Put64(end, cd_offset);
    Put32(end, 0x07064b50u);
    Put32(end, 0);  // the disk holding the ZIP64 end record
    Put64(end, end64_offset);
    Put32(end, 1);  // disks in all
  }
  // End of central directory record (4.3.16).
  const std::uint16_t count16 = zip64_end ? kMax16 : static_cast<std::uint16_t>(count);
  Put32(end, 0x06054b50u);
  Put16(end, 0);
  Put16(end, 0);
  Put16(end, count16);
  Put16(end, count16);
  Put32(end, zip64_end ? kMax32 : Clamp32(cd_size));
  Put32(end, zip64_end ? kMax32 : Clamp32(cd_offset));
  Put16(end, 0);  // comment length
  emit(end);
}

}  // namespace imuconv::pipeline
