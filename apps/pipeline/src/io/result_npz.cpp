// WriteResultNpz (imuconv/pipeline/result_arrays.h): the collected arrays and the sidecar as
// the members of a NumPy .npz archive (npz_writer.h).
#include <string>
#include <string_view>
#include <vector>

#include "imuconv/pipeline/result_arrays.h"
#include "npz_writer.h"

namespace imuconv::pipeline {
namespace {

/// The array's values as little-endian bytes: its own memory on a little-endian machine.
std::string_view LittleEndianBytes(const NdArray& a, std::vector<unsigned char>& swapped) {
  const void* p = a.type == NdArray::Type::kFloat64 ? static_cast<const void*>(a.data.data())
                                                    : static_cast<const void*>(a.integers.data());
  const std::size_t bytes = a.size() * 8;
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
  swapped.resize(bytes);
  const auto* in = static_cast<const unsigned char*>(p);
  for (std::size_t i = 0; i < bytes; i += 8)
    for (std::size_t b = 0; b < 8; ++b) swapped[i + b] = in[i + 7 - b];
  p = swapped.data();
#else
  (void)swapped;
#endif
  return {static_cast<const char*>(p), bytes};
}

}  // namespace

void WriteResultNpz(const ResultArrays& r, const std::function<void(std::string_view)>& sink,
                    bool force_zip64) {
  NpzWriter npz(sink, force_zip64);
  std::vector<unsigned char> swapped;
  for (const auto& [name, a] : r.arrays)
    npz.add(name, a.type == NdArray::Type::kFloat64 ? "<f8" : "<i8", a.shape,
            LittleEndianBytes(a, swapped));
  // The sidecar as a 0-d "<U{n}" array: UTF-32LE, one code unit per (ASCII) character.
  std::string utf32;
  utf32.reserve(4 * r.sidecar.size());
  for (char c : r.sidecar) {
    utf32 += c;
    utf32.append(3, '\0');
  }
  npz.add(kSidecarKey, "<U" + std::to_string(r.sidecar.size()), {}, utf32);
  npz.finish();
}

}  // namespace imuconv::pipeline
