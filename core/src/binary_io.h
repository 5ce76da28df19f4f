// Shared by the binary readers and writers of core (binary .msh, BINARY legacy .vtk, .vtu
// data): fixed-size integers and IEEE doubles in either byte order, and a cursor over a
// file read whole that checks every read against the bytes left, so that a count from a
// header is compared with what follows before anything is allocated for it. Internal: not
// installed.
//
// Messages of binary files name the file and the section or element ("file: what"): line
// numbers mean little in binary data.
#pragma once

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "voroclip/core.h"

namespace voroclip::detail {

// An unsigned integer of `size` (1 to 8) bytes at `b`, in the given byte order.
inline std::uint64_t load_uint(const unsigned char* b, std::size_t size, bool big_endian) {
  std::uint64_t v = 0;
  for (std::size_t i = 0; i < size; ++i) {
    const std::size_t j = big_endian ? i : size - 1 - i;
    v = (v << 8) | b[j];
  }
  return v;
}

// The same bits as a signed integer of `size` bytes (two's complement).
inline std::int64_t to_signed(std::uint64_t raw, std::size_t size) {
  if (size == 8) return static_cast<std::int64_t>(raw);
  const std::uint64_t sign = std::uint64_t{1} << (8 * size - 1);
  return static_cast<std::int64_t>(raw ^ sign) - static_cast<std::int64_t>(sign);
}

inline double bits_to_double(std::uint64_t raw) {
  double d;
  std::memcpy(&d, &raw, 8);
  return d;
}

inline double bits_to_float(std::uint64_t raw) {
  const auto r32 = static_cast<std::uint32_t>(raw);
  float f;
  std::memcpy(&f, &r32, 4);
  return static_cast<double>(f);
}

// Appends v as `sizeof(T)` little-endian bytes (any host byte order).
template <class T>
void put_le(std::string& out, T v) {
  std::uint64_t raw = 0;
  if constexpr (std::is_floating_point_v<T>) {
    static_assert(sizeof(T) == 8, "doubles only");
    std::memcpy(&raw, &v, 8);
  } else {
    raw = static_cast<std::uint64_t>(v);
  }
  for (std::size_t i = 0; i < sizeof(T); ++i) out += static_cast<char>((raw >> (8 * i)) & 0xff);
}

// A cursor over a whole file: binary values in the file's byte order, and the ASCII
// tokens and lines that binary formats put between their blocks.
class ByteReader {
 public:
  ByteReader(std::string path, const std::string& text, std::size_t pos = 0)
      : path_(std::move(path)), text_(text), pos_(pos) {}

  const std::string& path() const { return path_; }
  std::size_t pos() const { return pos_; }
  void seek(std::size_t pos) { pos_ = std::min(pos, text_.size()); }
  std::size_t remaining() const { return text_.size() - pos_; }
  void set_big_endian(bool big) { big_endian_ = big; }
  bool big_endian() const { return big_endian_; }

  [[noreturn]] void fail(const std::string& what) const { throw Error(path_ + ": " + what); }

  // Checks that `count` items of `size` bytes follow (no overflow); `what` says where, as
  // "section $Nodes: 5 nodes".
  void need(std::uint64_t count, std::uint64_t size, const std::string& what) const {
    if (size != 0 && count > remaining() / size) {
      fail(what + " needs " +
           (count > std::numeric_limits<std::uint64_t>::max() / size
                ? std::string("more than 2^64")
                : std::to_string(count * size)) +
           " bytes, the file has " + std::to_string(remaining()) + " left");
    }
  }

  // An unsigned integer of `size` bytes; `what` names it for a truncated file.
  std::uint64_t uint(std::size_t size, const char* what) {
    if (remaining() < size) {
      fail(std::string(what) + " is truncated: " + std::to_string(size) + " more bytes needed, " +
           std::to_string(remaining()) + " left");
    }
    const std::uint64_t v =
        load_uint(reinterpret_cast<const unsigned char*>(text_.data() + pos_), size, big_endian_);
    pos_ += size;
    return v;
  }
  std::int64_t sint(std::size_t size, const char* what) {
    return to_signed(uint(size, what), size);
  }
  double f64(const char* what) { return bits_to_double(uint(8, what)); }
  // Skips `count` items of `size` bytes.
  void skip(std::uint64_t count, std::uint64_t size, const std::string& what) {
    need(count, size, what);
    pos_ += static_cast<std::size_t>(count * size);
  }

  // The next ASCII token (blank-separated; empty at the end of the file), not consumed by
  // peek_token().
  std::string_view token() {
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
    const std::size_t begin = pos_;
    while (pos_ < text_.size() && !std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
    return std::string_view(text_).substr(begin, pos_ - begin);
  }
  std::string_view peek_token() {
    const std::size_t pos = pos_;
    const std::string_view t = token();
    pos_ = pos;
    return t;
  }
  // The blank-separated words of the next line that is not blank (empty at the end of
  // the file); the cursor moves to the start of the line after it.
  std::vector<std::string_view> words() {
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
    std::vector<std::string_view> out;
    while (pos_ < text_.size() && text_[pos_] != '\n') {
      if (std::isspace(static_cast<unsigned char>(text_[pos_]))) {
        ++pos_;
        continue;
      }
      const std::size_t begin = pos_;
      while (pos_ < text_.size() && !std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
      out.push_back(std::string_view(text_).substr(begin, pos_ - begin));
    }
    if (pos_ < text_.size()) ++pos_;
    return out;
  }
  // The rest of the current line, without its '\n' (the cursor moves past it).
  std::string_view rest_of_line() {
    const std::size_t begin = pos_;
    end_line();
    const std::size_t end = pos_ > begin && text_[pos_ - 1] == '\n' ? pos_ - 1 : pos_;
    return std::string_view(text_).substr(begin, end - begin);
  }
  // Skips the rest of the current line and its '\n' (binary data starts on the next line).
  void end_line() {
    while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
    if (pos_ < text_.size()) ++pos_;
  }
  // The 1-based line of the cursor (for ASCII parts of a binary file read by a Lexer).
  std::uint32_t line() const {
    return 1u + static_cast<std::uint32_t>(std::count(
                    text_.begin(), text_.begin() + static_cast<std::ptrdiff_t>(pos_), '\n'));
  }

 private:
  std::string path_;
  const std::string& text_;
  std::size_t pos_;
  bool big_endian_ = false;
};

}  // namespace voroclip::detail
