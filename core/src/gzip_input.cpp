// Compressed input: a file whose bytes start with gzip's magic (RFC 1952: 1f 8b) is
// inflated before any reader parses it (text_lexer.h, read_whole_file / read_whole_stream),
// so that every format is read gzip-compressed too, whatever the file's name; a name ending
// in .gz is read by the extension before it (bunny.obj.gz: OBJ).
#include <zlib.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <string_view>

#include "text_lexer.h"

namespace voroclip::detail {

namespace {

// Deflate's largest expansion (zlib's "maximum compression factor", 1032:1): more output
// than this per byte of input is not deflate data but a corrupt stream or a bomb.
constexpr std::uint64_t kMaxRatio = 1032;

}  // namespace

std::string gunzip(const std::string& name, std::string_view data) {
  z_stream zs{};
  // 15 + 16: a gzip wrapper (not zlib's), the largest window.
  if (inflateInit2(&zs, 15 + 16) != Z_OK) throw Error(name + ": zlib's inflate cannot start");
  struct End {
    z_stream* z;
    ~End() { inflateEnd(z); }
  } end{&zs};
  std::string out;
  const std::uint64_t limit = kMaxRatio * data.size() + 1024;
  std::size_t given = 0;  // bytes of `data` handed to inflate so far
  for (;;) {
    if (zs.avail_in == 0 && given < data.size()) {
      const std::size_t n = std::min<std::size_t>(data.size() - given, std::size_t{1} << 30);
      zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data.data() + given));
      zs.avail_in = static_cast<uInt>(n);
      given += n;
    }
    const std::size_t have = out.size();
    if (have >= limit) {
      throw Error(name + ": the gzip data inflates to more than 1032 times its size: corrupt");
    }
    out.resize(static_cast<std::size_t>(
        std::min<std::uint64_t>(limit, std::max<std::size_t>(65536, 2 * have))));
    zs.next_out = reinterpret_cast<Bytef*>(out.data() + have);
    zs.avail_out = static_cast<uInt>(std::min<std::size_t>(out.size() - have, 1u << 30));
    const std::size_t room = zs.avail_out;
    const int status = inflate(&zs, Z_NO_FLUSH);
    out.resize(have + (room - zs.avail_out));
    if (status == Z_STREAM_END) {
      const std::size_t next = given - zs.avail_in;  // the first byte after this member
      if (next == data.size()) return out;
      // gzip files may be concatenated: another member goes on; anything else is an error.
      if (is_gzip(data.substr(next))) {
        inflateReset(&zs);
        continue;
      }
      throw Error(name + ": " + std::to_string(data.size() - next) +
                  " bytes follow the end of the gzip data");
    }
    if (status == Z_OK) continue;
    if (status == Z_BUF_ERROR && (zs.avail_in > 0 || given < data.size())) continue;
    if (status == Z_BUF_ERROR) throw Error(name + ": the gzip data is truncated");
    throw Error(name + ": corrupt gzip data (zlib: " + (zs.msg != nullptr ? zs.msg : "error") +
                ")");
  }
}

}  // namespace voroclip::detail
