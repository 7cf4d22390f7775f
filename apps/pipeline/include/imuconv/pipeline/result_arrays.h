// The numbers of an output document (what `imuconv run` writes as JSON) as named N-d arrays,
// plus a JSON sidecar with everything else: what `imuconv run -o OUT.npz` writes, and what a
// caller (the Python module) gets without writing a file. The rule, in full (also in
// docs/interop.md):
//
// Keys. A value's key is its JSON pointer without the leading '/', member names escaped as
// RFC 6901 says ('~' as "~0", '/' as "~1"), with two changes:
//   - an element of the top-level "tasks" array is named by its "name" (which must be its
//     first member), not its index: "tasks/kf_rk4/...";
//   - the index of an element of any other array of objects (an array whose first element is
//     an object; every element must then be one) is removed: the values at one key are
//     stacked over the elements, the outer array first. "tasks/kf_rk4/measurements/3/J_bias/matrix"
//     is element 3 of key "tasks/kf_rk4/measurements/J_bias/matrix", shape (n, 9, 6).
// Arrays. A value that is a rectangular array of numbers (nested arrays of equal lengths, at
// least one number, numbers only at the innermost level) is an N-d array: a 15x15 matrix is
// shape (15, 15). Stacked over arrays of objects of lengths n1, n2, ..., it is shape
// (n1, n2, ..., 15, 15). A number alone is a 0-d value: stacked it makes shape (n1, ...); one
// inside no array of objects ("noise/gyro_noise_density", "imu/samples") goes to the sidecar.
// Types. A key whose numbers are all JSON integers (no '.' or exponent: indices, counts,
// "*_abs_ns" nanoseconds) is int64; otherwise float64, each number the double the JSON text
// reads back to (the writer prints the shortest text that does), so bit for bit. A key mixing
// integers and reals is float64 when every integer is exact in a double, else an error.
// Irregular keys. When the stacked values of a key do not fill the grid of its arrays of
// objects exactly (a value missing in some element, shapes that differ, arrays of objects of
// differing lengths), nothing is padded: each value is written alone under its own pointer
// with the indices kept ("tasks/pred/steps/7/ground_truth/position_error_m"), as its own
// shape. The same holds for the sidecar's values.
// Sidecar. Member "meta" (kSidecarKey) holds JSON text:
//   {"format": "imuconv-npz", "format_version": 1,
//    "values": {KEY: VALUE, ...},          every value that is not in an array: strings,
//                                          booleans, nulls, numbers inside no array of objects,
//                                          empty arrays and objects, arrays that are not
//                                          rectangular arrays of numbers (block labels);
//                                          one stacked key whose value is the same in every
//                                          element is listed once, else per element as above
//    "stacked_over": {KEY: [ARRAY, ...]}}  for each stacked array: the arrays of objects its
//                                          leading axes run over, outermost first
// Order: arrays and values in the order of their first occurrence in the document.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "imuconv/registry.h"  // imuconv::Error, thrown for documents that cannot be collected

namespace imuconv::pipeline {

/// An N-d array in C order; exactly one of data / integers holds its values.
struct NdArray {
  enum class Type { kFloat64, kInt64 };
  Type type = Type::kFloat64;
  std::vector<std::size_t> shape;      ///< empty: a 0-d array (one value)
  std::vector<double> data;            ///< kFloat64
  std::vector<std::int64_t> integers;  ///< kInt64
  std::size_t size() const noexcept {
    return type == Type::kFloat64 ? data.size() : integers.size();
  }
};

struct ResultArrays {
  std::vector<std::pair<std::string, NdArray>> arrays;  ///< key, array; document order
  std::string sidecar;                                  ///< the sidecar's JSON text (ASCII)
};

/// The sidecar's key in the archive (member "meta.npy"): a 0-d NumPy unicode array ("<U{n}")
/// holding the JSON text; `json.loads(str(np.load(path)["meta"]))` reads it.
inline constexpr const char* kSidecarKey = "meta";

/// Reads an output document's text and returns its arrays and sidecar. `what` names the text
/// in messages (e.g. "the output of examples/x.json"). Throws imuconv::Error naming `what` and
/// a JSON pointer for text that is not JSON, a task without a leading "name", an array mixing
/// objects with other values, a duplicate key, a key mixing integers beyond 2^53 with reals, or
/// two values that would get the same key. Holds only the numbers (8 bytes each) and the
/// sidecar, never the text: the FILE* form reads the text from a (temporary) file. Objects and
/// arrays may nest at most 256 deep.
ResultArrays CollectResultArrays(std::FILE* text, const std::string& what);
ResultArrays CollectResultArrays(std::string_view text, const std::string& what);

/// Writes `r` as a NumPy .npz archive (format 1.0 members, "<f8" / "<i8" little-endian, C
/// order, stored; the sidecar as member kSidecarKey) into `sink`, in pieces. ZIP64 records are
/// written when the archive needs them (past 4 GiB, or 65535 members or more); `force_zip64` writes
/// them always (for tests).
void WriteResultNpz(const ResultArrays& r, const std::function<void(std::string_view)>& sink,
                    bool force_zip64 = false);

}  // namespace imuconv::pipeline
