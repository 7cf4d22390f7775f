// A streaming JSON text writer with the layout of PrettyJson: objects one key per line,
// indented by two spaces per level; arrays of scalars (vectors, matrix rows) on one line.
//
// Numbers are written in the shortest form that reads back to the same double (the digits
// std::to_chars gives), laid out as nlohmann::json does:
// ".0" on integral values so that they stay floating point, exponents from 1e-05 / 1e+16.
// The writer keeps the JSON pointer of the value being written, so that a non-finite number
// (which JSON cannot hold) is reported where it is: "produced a non-finite number (output
// /tasks/0/cov/matrix/3/4); no output is written" (or written as null, if so configured).
//
// Pieces of one document can be written by independent writers (e.g. on several threads)
// and spliced in order: a writer made with the depth and pointer of the element it writes
// produces exactly the text the parent writer would have produced; the parent writes the
// separators (element_separator) and counts the elements (skip_elements).
//
// Form::kEvents writes the same calls as compact binary records of typed values instead of text
// (src/io/value_events.h; in-process only): what `imuconv run -o OUT.npz` collects its arrays
// from, without formatting numbers as text and parsing them back, each vector and matrix whole
// with its shape. Splicing works the same way (element_separator is then empty).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "imuconv/pipeline/json_check.h"

namespace imuconv::pipeline {

class JsonWriter {
 public:
  enum class NonFinite {
    Throw,  ///< throw imuconv::Error naming the output pointer (pipeline outputs)
    Null,   ///< write null, as nlohmann::json's dump does
  };
  enum class Form {
    kText,    ///< JSON text
    kEvents,  ///< value events (src/io/value_events.h), for the result-array collector
  };

  /// Appends to `out`. `depth` is the indentation level of the first value's contents (0 for
  /// a whole document; JsonWriter::content_depth() of the parent for a spliced element) and
  /// `pointer` the JSON pointer of that value.
  explicit JsonWriter(std::string& out, int depth = 0, std::string pointer = {},
                      NonFinite non_finite = NonFinite::Throw, Form form = Form::kText);

  // ---- containers -------------------------------------------------------------------------
  void begin_object();
  void end_object();
  /// An array with one element per line (objects, matrices).
  void begin_array();
  /// An array on one line; for scalars only.
  void begin_line_array();
  void end_array();
  /// The next member's key (inside an object); its value follows.
  void key(std::string_view k);

  // ---- scalars: an object member (after key()) or an array element -------------------------
  void number(double v);
  void integer(std::int64_t v);
  void unsigned_integer(std::uint64_t v);
  void boolean(bool b);
  void string(std::string_view s);
  void null();

  // ---- composites ---------------------------------------------------------------------------
  /// A one-line array of n numbers.
  void numbers(const double* v, std::size_t n);
  template <typename Derived>
  void vector(const Eigen::DenseBase<Derived>& v) {
    double buf[32];
    double* p = buf;
    if (v.size() > 32) {
      scratch_.resize(static_cast<std::size_t>(v.size()));
      p = scratch_.data();
    }
    for (Eigen::Index i = 0; i < v.size(); ++i) p[i] = v.derived().coeff(i);
    numbers(p, static_cast<std::size_t>(v.size()));
  }
  /// A matrix as an array of rows (row-major), each row on one line. As value events, one
  /// record with its shape (when its numbers are finite; else row by row, as the text).
  template <typename Derived>
  void matrix(const Eigen::DenseBase<Derived>& m) {
    const auto rows = static_cast<std::size_t>(m.rows()), cols = static_cast<std::size_t>(m.cols());
    if (events_) {
      scratch_.resize(rows * cols);
      for (std::size_t i = 0; i < rows; ++i)
        for (std::size_t k = 0; k < cols; ++k)
          scratch_[i * cols + k] =
              m.derived().coeff(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(k));
      if (whole_matrix(scratch_.data(), rows, cols)) return;
    }
    begin_array();
    double row[32];
    for (Eigen::Index i = 0; i < m.rows(); ++i) {
      if (m.cols() <= 32) {
        for (Eigen::Index k = 0; k < m.cols(); ++k) row[k] = m.derived().coeff(i, k);
        numbers(row, cols);
      } else {
        begin_line_array();
        for (Eigen::Index k = 0; k < m.cols(); ++k) number(m.derived().coeff(i, k));
        end_array();
      }
    }
    end_array();
  }
  void string_list(const std::vector<std::string>& v);
  /// Any nlohmann::json value in the same layout (keys in the json's own order).
  void value(const json& j);

  // ---- splicing -------------------------------------------------------------------------------
  /// For array elements that other writers produce (made with content_depth() and the
  /// element's pointer, container_pointer() + "/" + index, of this writer's open multi-line
  /// array) and whose text goes straight to the output: what goes before the next element
  /// (`first`) or any later one, and then skip_elements(n) to count them.
  std::string element_separator(bool first) const;
  Form form() const noexcept { return form_; }
  void skip_elements(std::size_t n);
  /// The indentation level of the open container's contents.
  int content_depth() const noexcept;
  /// The pointer of the open container.
  std::string container_pointer() const;
  /// The pointer of the value being written (for messages).
  std::string pointer() const;

 private:
  struct Frame {
    bool object = false;
    bool one_line = false;
    std::size_t count = 0;
    std::string key;  // objects: the current member
  };
  void before_value();
  void open(bool object, bool one_line, char c);
  void close(char c);
  void append_number(double v);
  /// Form::kEvents: the matrix (row-major) as one 'm' record, if its numbers are all finite.
  bool whole_matrix(const double* v, std::size_t rows, std::size_t cols);
  [[noreturn]] void non_finite() const;
  /// A string or key that is not well-formed UTF-8 (byte `at` of `s`), at output `where`.
  [[noreturn]] void not_utf8(std::string_view s, std::size_t at, const std::string& where) const;
  std::string pointer_upto(std::size_t frames) const;

  std::string& out_;
  int depth_;           // base depth
  int open_lines_ = 0;  // multi-line containers open
  std::string pointer_;
  NonFinite non_finite_;
  Form form_;
  bool events_;  // form_ == Form::kEvents
  std::vector<Frame> stack_;
  std::vector<double> scratch_;  // a long vector's or a matrix's numbers, gathered
};

}  // namespace imuconv::pipeline
