// Shared by the file readers and writers of core (tetmesh_io.cpp, surface_io.cpp): a
// tokenizer that keeps line numbers for messages, strict number parsing, counted sections
// that report truncation, and small text helpers. Internal: not installed.
#pragma once

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>

#include "voroclip/core.h"

namespace voroclip::detail {

inline std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

// A token as it may appear in a message: at most 40 characters, a byte that is not
// printable ASCII escaped as \xHH (a binary file read by mistake must not put control
// bytes on the terminal, and the escape shows what the byte was: \xef\xbb\xbf a BOM).
inline std::string escape(std::string_view t, std::size_t max_size = 40) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string out;
  for (std::size_t i = 0; i < t.size() && i < max_size; ++i) {
    const auto c = static_cast<unsigned char>(t[i]);
    if (c >= 0x20 && c < 0x7f) {
      out += static_cast<char>(c);
    } else {
      out += "\\x";
      out += kHex[c >> 4];
      out += kHex[c & 15];
    }
  }
  if (t.size() > max_size) out += "...";
  return out;
}

inline std::string quote(std::string_view t) { return "'" + escape(t) + "'"; }

inline bool is_gzip(std::string_view data) {
  return data.size() >= 2 && static_cast<unsigned char>(data[0]) == 0x1f &&
         static_cast<unsigned char>(data[1]) == 0x8b;
}

// The bytes that gzip `data` inflates to (its members one after the other); `name` stands
// for the file in messages (corrupt, truncated or followed by other bytes). gzip_input.cpp.
std::string gunzip(const std::string& name, std::string_view data);

// The bytes of a stream up to its end, inflated when they are gzip data (is_gzip: every
// reader reads compressed files); `name` stands for the file in messages.
inline std::string read_whole_stream(std::istream& in, const std::string& name) {
  std::ostringstream ss;
  if (in.peek() != std::char_traits<char>::eof()) ss << in.rdbuf();
  if (in.bad()) throw Error(name + ": read error");
  std::string bytes = ss.str();
  if (is_gzip(bytes)) return gunzip(name, bytes);
  return bytes;  // (moved: a conditional expression would copy the whole file)
}

// A directory opens as a file but reads as an error ("read error"): named as what it is.
// The readers call it before they look at the extension, so that `dir` and `dir.obj`
// alike are reported as directories.
inline void check_not_directory(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    throw Error(path + ": is a directory, not a file");
  }
}

inline std::string read_whole_file(const std::string& path) {
  check_not_directory(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path + ": cannot open the file");
  return read_whole_stream(in, path);
}

// A file named NAME.EXT.gz is read as NAME.EXT (the bytes are inflated by
// read_whole_file whatever the name); one named NAME.gz, with no extension before .gz, has
// no format to be read as.
inline void check_not_gzip_name(const std::string& path) {
  std::string ext = path.size() >= 3 ? path.substr(path.size() - 3) : std::string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".gz") {
    throw Error(path +
                ": a compressed file is read by the extension before .gz (bunny.obj.gz "
                "as an OBJ), and this one has none that voroclip reads");
  }
}
// Bytes still gzip data after read_whole_file inflated them: compressed twice.
inline void check_not_gzip(const std::string& path, std::string_view data) {
  if (is_gzip(data)) {
    throw Error(path +
                ": the data is gzip-compressed twice (after inflating, it starts with the bytes "
                "1f 8b again): decompress it once more (gunzip)");
  }
}

// What every reader does to a file's bytes before it parses them (the binary STL reader
// after it has recognised a binary file by its size, whose 80-byte header is arbitrary):
//  - a gzip-compressed file is reported as such (check_not_gzip);
//  - a UTF-8 byte order mark (EF BB BF), which Windows editors put at the start of text
//    files, is dropped: no format gives these bytes a meaning at the start of a file;
//  - a text whose lines end in CR alone (classic Mac OS), with no LF anywhere, gets LF
//    line ends. A file with control bytes other than blanks is binary data (a binary PLY,
//    .msh or .vtk whose header lines would end in CR) and is left as it is, so that no
//    byte of its data is changed. CRLF needs nothing: CR is a blank to every tokenizer.
inline void prepare_input(const std::string& path, std::string& text) {
  check_not_gzip(path, text);
  if (text.size() >= 3 && text.compare(0, 3, "\xef\xbb\xbf") == 0) text.erase(0, 3);
  if (text.find('\r') == std::string::npos || text.find('\n') != std::string::npos) return;
  for (const char ch : text) {
    const auto c = static_cast<unsigned char>(ch);
    if (c < 0x20 && c != '\t' && c != '\r' && c != '\v' && c != '\f') return;
  }
  std::replace(text.begin(), text.end(), '\r', '\n');
}

// Splits a text into tokens separated by blanks; `comment` (0: none) starts a comment that
// runs to the end of its line.
class Lexer {
 public:
  // `first_line`: the line number of the text's first line (a text that is the tail of a
  // file, after a header read apart).
  Lexer(std::string path, std::string text, char comment, std::uint32_t first_line = 1)
      : path_(std::move(path)),
        text_(std::move(text)),
        comment_(comment),
        line_(first_line),
        tok_line_(first_line) {}

  const std::string& path() const { return path_; }
  const std::string& text() const { return text_; }

  // The next token on any line; empty at the end of the text. line() is then its line.
  std::string_view next() {
    skip_blanks(true);
    return take();
  }
  // The next token on any line, not consumed (line() is left as it was).
  std::string_view peek() {
    const std::size_t pos = pos_;
    const std::uint32_t line = line_, tok_line = tok_line_;
    const std::string_view t = next();
    pos_ = pos;
    line_ = line;
    tok_line_ = tok_line;
    return t;
  }
  // The next token if it is on the current line, else empty (nothing is consumed).
  std::string_view next_on_line() {
    skip_blanks(false);
    if (pos_ < text_.size() && text_[pos_] == '\n') return {};
    return take();
  }
  // Skips the rest of the current line.
  void skip_line() {
    while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
  }
  // Skips whole lines up to and including the next line that is empty or blank.
  void skip_to_blank_line() {
    skip_line();
    while (pos_ < text_.size()) {
      ++pos_;
      ++line_;
      std::size_t end = pos_;
      while (end < text_.size() && text_[end] != '\n' &&
             std::isspace(static_cast<unsigned char>(text_[end]))) {
        ++end;
      }
      if (end == text_.size() || text_[end] == '\n') {
        pos_ = end;
        return;
      }
      pos_ = end;
      skip_line();
    }
  }
  // The rest of the current line, verbatim (for free-text lines such as a VTK title).
  std::string_view rest_of_line() {
    const std::size_t begin = pos_;
    skip_line();
    tok_line_ = line_;
    return std::string_view(text_).substr(begin, pos_ - begin);
  }
  // Moves to the start of the next line.
  void next_line() {
    skip_line();
    if (pos_ < text_.size()) {
      ++pos_;
      ++line_;
    }
  }

  // The line of the last token (at the end of the text: the last line).
  std::uint32_t line() const { return tok_line_; }
  std::string at() const { return path_ + ":" + std::to_string(tok_line_) + ": "; }
  [[noreturn]] inline void fail(const std::string& what) const { throw Error(at() + what); }

 private:
  void skip_blanks(bool cross_lines) {
    while (pos_ < text_.size()) {
      const char c = text_[pos_];
      if (c == '\n') {
        if (!cross_lines) return;
        ++line_;
        ++pos_;
      } else if (comment_ != 0 && c == comment_) {
        skip_line();
      } else if (std::isspace(static_cast<unsigned char>(c))) {
        ++pos_;
      } else {
        return;
      }
    }
  }
  std::string_view take() {
    if (pos_ == text_.size()) {
      // The last line that holds anything: a final newline does not open a line.
      tok_line_ = line_ - (line_ > 1 && !text_.empty() && text_.back() == '\n' ? 1u : 0u);
      return {};
    }
    const std::size_t begin = pos_;
    while (pos_ < text_.size() && !std::isspace(static_cast<unsigned char>(text_[pos_])) &&
           (comment_ == 0 || text_[pos_] != comment_)) {
      ++pos_;
    }
    tok_line_ = line_;
    return std::string_view(text_).substr(begin, pos_ - begin);
  }

  std::string path_;
  std::string text_;
  char comment_;
  std::size_t pos_ = 0;
  std::uint32_t line_ = 1;      // line of text_[pos_]
  std::uint32_t tok_line_ = 1;  // line of the last token
};

// A token that ends a counted section early: a section keyword (Medit "Triangles", VTK
// "CELLS", Gmsh "$EndNodes"), as opposed to a malformed number ("1.5x", "nan").
inline bool is_keyword(std::string_view t) {
  if (t.empty()) return false;
  if (t[0] == '$') return true;
  if (!std::isalpha(static_cast<unsigned char>(t[0])) || t.size() < 3) return false;
  for (char c : t) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') return false;
  }
  const std::string l = lower(t);
  return l != "nan" && l != "inf" && l != "infinity";
}

// A section announcing `expected` entries, of which `found` were read so far.
struct Section {
  std::string name;   // as in the file: "Vertices", "$Nodes", "POINTS"
  const char* entry;  // what an entry is, plural: "vertices", "nodes"
  std::uint64_t expected;
  std::uint64_t found = 0;
};

[[noreturn]] inline void truncated(const Lexer& lx, const Section& s, std::string_view t) {
  lx.fail("section " + s.name + " is truncated: expected " + std::to_string(s.expected) + " " +
          s.entry + ", found " + std::to_string(s.found) +
          (t.empty() ? " before the end of the file" : " before " + quote(t)));
}

// The next token inside a counted section (see truncated()).
inline std::string_view entry_token(Lexer& lx, const Section& s) {
  const std::string_view t = lx.next();
  if (t.empty() || is_keyword(t)) truncated(lx, s, t);
  return t;
}

inline double to_double(const Lexer& lx, std::string_view t) {
  std::string_view s = t;
  if (s.size() > 1 && s[0] == '+' && s[1] != '-' && s[1] != '+') s.remove_prefix(1);
  double v = 0;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  if (r.ec == std::errc::result_out_of_range) {
    lx.fail(quote(t) + " is out of the range of a double");
  }
  if (r.ec != std::errc() || r.ptr != s.data() + s.size()) lx.fail(quote(t) + " is not a number");
  if (!std::isfinite(v)) lx.fail(quote(t) + " is not a finite number");
  return v;
}

// A non-negative integer (a count, an index, a tag, a type).
inline std::uint64_t to_uint(const Lexer& lx, std::string_view t, const char* what) {
  std::string_view s = t;
  if (s.size() > 1 && s[0] == '+' && s[1] != '-' && s[1] != '+') s.remove_prefix(1);
  std::uint64_t v = 0;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  if (r.ec != std::errc() || r.ptr != s.data() + s.size()) {
    lx.fail(quote(t) + " is not a valid " + what + " (a non-negative integer)");
  }
  return v;
}

// A count from a header, that the memory reserved for it cannot blow up on a bad file.
inline std::size_t reserve_for(const Lexer& lx, std::uint64_t count) {
  return static_cast<std::size_t>(std::min<std::uint64_t>(count, lx.text().size() / 2 + 1));
}

// The next token as a number, in a counted section.
inline double entry_double(Lexer& lx, const Section& s) {
  return to_double(lx, entry_token(lx, s));
}
inline std::uint64_t entry_uint(Lexer& lx, const Section& s, const char* what) {
  return to_uint(lx, entry_token(lx, s), what);
}

// The next header value (a count, a version...): a missing value is reported as such.
inline std::string_view header_token(Lexer& lx, const std::string& header) {
  const std::string_view t = lx.next();
  if (t.empty()) lx.fail(header + ": missing value before the end of the file");
  return t;
}

[[noreturn]] inline void fail_at(const std::string& path, std::uint32_t line,
                                 const std::string& what) {
  throw Error(path + ":" + std::to_string(line) + ": " + what);
}

inline void append(std::string& out, double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof(buf), v);
  out.append(buf, r.ptr);
}
inline void append(std::string& out, std::uint64_t v) {
  char buf[24];
  const auto r = std::to_chars(buf, buf + sizeof(buf), v);
  out.append(buf, r.ptr);
}

inline void write_text(const std::string& path, const std::string& text) {
  write_file_atomically(path, [&](std::ostream& out) {
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
  });
}

inline std::string extension_of(const std::string& path) {
  const std::size_t slash = path.find_last_of("/\\");
  const std::size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  return lower(path.substr(dot));
}

// The extension a file is read by: extension_of, or for NAME.EXT.gz (a compressed file,
// inflated by read_whole_file) that of NAME.EXT.
inline std::string input_extension_of(const std::string& path) {
  const std::string ext = extension_of(path);
  return ext == ".gz" ? extension_of(path.substr(0, path.size() - 3)) : ext;
}

inline std::string without_extension(const std::string& path) {
  return extension_of(path).empty() ? path : path.substr(0, path.find_last_of('.'));
}

// The cell data arrays of VTK files (.vtk, .vtu) that hold tags: voroclip's own `region`
// (tets) and `patch` (triangles), and meshio's names for the tags of the formats it
// converts from, "gmsh:physical" (Gmsh's physical tags, from .msh) and "medit:ref"
// (Medit's refs, from .mesh), one array for tets and triangles alike. The tets' tags are
// the first array present in the order kVtkTetTags gives, the triangles' in the order of
// kVtkTriangleTags. Other cell data ("gmsh:geometrical", the entity tags, "cell_id", ...)
// is not read as tags.
inline constexpr const char* kVtkTagNames[] = {"region", "patch", "gmsh:physical", "medit:ref"};
inline constexpr std::size_t kVtkTetTags[] = {0, 2, 3};
inline constexpr std::size_t kVtkTriangleTags[] = {1, 2, 3};

// The reader of VTK XML unstructured grids behind read_tet_mesh (vtu_io.cpp).
TetMeshInput read_vtu_tet_mesh(const std::string& path, std::string text);

}  // namespace voroclip::detail
