#include "io/read_medit_mesh.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string_view>
#include <system_error>

namespace femorph {
namespace {

bool iequals(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (std::tolower(static_cast<unsigned char>(a[i])) !=
        std::tolower(static_cast<unsigned char>(b[i])))
      return false;
  }
  return true;
}

/// Tokens of data (numbers, or quoted strings in sections such as Geometry)
/// as opposed to keywords, which start with a letter.
bool is_data_token(std::string_view t) {
  if (t.empty()) return false;
  const char c = t.front();
  return (c >= '0' && c <= '9') || c == '-' || c == '+' || c == '.' || c == '"';
}

/// Keywords that can follow a section, to tell a section cut short from a
/// stray word.
bool is_medit_keyword(std::string_view t) {
  static constexpr std::string_view kKeywords[] = {
      "MeshVersionFormatted", "Dimension", "Vertices", "Edges", "Triangles",
      "Quadrilaterals", "Tetrahedra", "Prisms", "Hexahedra", "Corners", "Ridges",
      "RequiredVertices", "RequiredEdges", "RequiredTriangles", "Normals",
      "NormalAtVertices", "NormalAtTriangleVertices", "Tangents", "TangentAtVertices",
      "TangentAtEdges", "Identifier", "Geometry", "End"};
  for (std::string_view k : kKeywords)
    if (iequals(t, k)) return true;
  return false;
}

/// Whitespace-separated tokens over the whole file in memory, skipping `#`
/// comments and counting lines for the error messages. No allocation per
/// token.
class Tokenizer {
 public:
  Tokenizer(const char* begin, const char* end) : p_(begin), end_(end) {}

  /// Next token, empty at the end of the input.
  std::string_view next() {
    skip_blanks();
    line_of_token_ = line_;
    const char* start = p_;
    while (p_ != end_ && !is_blank(*p_) && *p_ != '#') ++p_;
    return {start, static_cast<std::size_t>(p_ - start)};
  }

  std::string_view peek() const {
    Tokenizer copy = *this;
    return copy.next();
  }

  /// Line (1-based) of the token last returned by next().
  long line() const { return line_of_token_; }
  std::size_t bytes_left() const { return static_cast<std::size_t>(end_ - p_); }

 private:
  static bool is_blank(char c) {
    return c == ' ' || c == '\n' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
  }

  void skip_blanks() {
    while (p_ != end_) {
      const char c = *p_;
      if (c == '\n') {
        ++line_;
        ++p_;
      } else if (is_blank(c)) {
        ++p_;
      } else if (c == '#') {
        while (p_ != end_ && *p_ != '\n') ++p_;
      } else {
        break;
      }
    }
  }

  const char* p_;
  const char* end_;
  long line_ = 1;
  long line_of_token_ = 1;
};

bool parse_double(std::string_view t, double& value) {
  if (!t.empty() && t.front() == '+') t.remove_prefix(1);  // from_chars rejects '+'
  const char* end = t.data() + t.size();
  const auto result = std::from_chars(t.data(), end, value);
  return result.ec == std::errc() && result.ptr == end;
}

bool parse_integer(std::string_view t, long long& value) {
  if (!t.empty() && t.front() == '+') t.remove_prefix(1);
  const char* end = t.data() + t.size();
  const auto result = std::from_chars(t.data(), end, value);
  return result.ec == std::errc() && result.ptr == end;
}

class MeditReader {
 public:
  MeditReader(const std::string& path, const std::string& text, MeditMesh& mesh)
      : path_(path), tok_(text.data(), text.data() + text.size()), mesh_(mesh) {}

  Status run() {
    std::string_view t = tok_.next();
    if (!iequals(t, "MeshVersionFormatted"))
      return fail_here("not an ASCII Medit file: expected 'MeshVersionFormatted', found " +
                       quoted(t));
    long long version = 0;
    if (Status s = read_integer("the MeshVersionFormatted value", version); !s) return s;
    // Versions differ in binary precision only; the ASCII text is the same.
    if (version < 1 || version > 4)
      return fail_here("MeshVersionFormatted " + std::to_string(version) +
                       " is not supported (expected 1 to 4)");

    while (true) {
      t = tok_.next();
      if (t.empty() || iequals(t, "End")) break;
      // Dimension is a header line, not a section of entries.
      section_ = iequals(t, "Dimension") ? std::string() : std::string(t);
      Status s;
      if (iequals(t, "Dimension")) {
        s = read_dimension();
      } else if (iequals(t, "Vertices")) {
        s = read_vertices();
      } else if (iequals(t, "Tetrahedra")) {
        s = read_elements<4>(mesh_.tets, mesh_.tet_refs, seen_tets_);
      } else if (iequals(t, "Triangles")) {
        s = read_elements<3>(mesh_.triangles, mesh_.triangle_refs, seen_triangles_);
      } else {
        skip_section();
      }
      if (!s) return s;
    }
    section_.clear();
    if (!seen_vertices_) return fail("no Vertices section");
    // Elements listed before the Vertices section could not be checked then.
    if (Status s = check_indices("Tetrahedra", mesh_.tets); !s) return s;
    return check_indices("Triangles", mesh_.triangles);
  }

 private:
  static std::string quoted(std::string_view t) {
    if (t.empty()) return "the end of the file";
    return "'" + std::string(t.substr(0, 40)) + (t.size() > 40 ? "...'" : "'");
  }

  Status fail(const std::string& what) const { return Status::failure(path_ + ": " + what); }

  Status fail_here(const std::string& what) const {
    std::string where = path_ + ":" + std::to_string(tok_.line()) + ": ";
    if (!section_.empty()) where += "section " + section_ + ": ";
    return Status::failure(where + what);
  }

  /// Error for a token that should have been entry `entry` (0-based) of a
  /// section of `count`: tells a truncated section from a bad token.
  Status bad_entry_token(std::string_view t, long long entry, long long count,
                         const char* what) const {
    const std::string progress =
        "entry " + std::to_string(entry + 1) + " of " + std::to_string(count);
    if (t.empty())
      return fail(
          "unexpected end of file in section " + section_ + " at " + progress +
          " (truncated file: only " + std::to_string(entry) + " complete entries)");
    if (is_medit_keyword(t))
      return fail_here("truncated at " + progress + " (only " + std::to_string(entry) +
                       " complete entries): found keyword " + quoted(t));
    double as_real = 0.0;
    if (parse_double(t, as_real))
      return fail_here(progress + ": expected " + what + " (an integer), found " + quoted(t));
    return fail_here(progress + ": expected " + what + ", found non-numeric token " +
                     quoted(t));
  }

  Status read_integer(const char* what, long long& value) {
    const std::string_view t = tok_.next();
    if (t.empty()) return fail_here(std::string("unexpected end of file: expected ") + what);
    if (!parse_integer(t, value))
      return fail_here(std::string("expected ") + what + " (an integer), found " + quoted(t));
    return Status::success();
  }

  Status read_count(long long& count) {
    if (Status s = read_integer("the number of entries", count); !s) return s;
    if (count < 0) return fail_here("negative number of entries " + std::to_string(count));
    if (count > std::numeric_limits<index_t>::max())
      return fail_here("number of entries " + std::to_string(count) + " exceeds 32-bit indices");
    return Status::success();
  }

  /// Reserve for `count` entries, but no more than the rest of the file can
  /// hold: a corrupt count must not allocate gigabytes before failing.
  template <class V>
  void reserve_for(V& v, long long count, int fields) {
    const std::size_t fit = tok_.bytes_left() / (2 * static_cast<std::size_t>(fields)) + 1;
    v.reserve(std::min(static_cast<std::size_t>(count), fit));
  }

  Status read_dimension() {
    long long dim = 0;
    if (Status s = read_integer("the dimension", dim); !s) return s;
    if (dim != 3)
      return fail_here("Dimension " + std::to_string(dim) +
                       " is not supported: only 3D meshes (Dimension 3) can be read");
    return Status::success();
  }

  Status read_ref(long long entry, long long count, index_t& ref) {
    const std::string_view t = tok_.next();
    long long value = 0;
    if (!parse_integer(t, value)) return bad_entry_token(t, entry, count, "a reference number");
    if (value < std::numeric_limits<index_t>::min() || value > std::numeric_limits<index_t>::max())
      return fail_here("entry " + std::to_string(entry + 1) + ": reference " + quoted(t) +
                       " does not fit in 32 bits");
    ref = static_cast<index_t>(value);
    return Status::success();
  }

  Status read_vertices() {
    if (seen_vertices_) return fail_here("section given twice");
    seen_vertices_ = true;
    long long count = 0;
    if (Status s = read_count(count); !s) return s;
    reserve_for(mesh_.points, count, 4);
    reserve_for(mesh_.point_refs, count, 4);
    for (long long i = 0; i < count; ++i) {
      Vec3 p;
      for (int k = 0; k < 3; ++k) {
        const std::string_view t = tok_.next();
        if (!parse_double(t, p[k])) return bad_entry_token(t, i, count, "a coordinate");
      }
      index_t ref = 0;
      if (Status s = read_ref(i, count, ref); !s) return s;
      mesh_.points.push_back(p);
      mesh_.point_refs.push_back(ref);
    }
    return Status::success();
  }

  template <std::size_t N>
  Status read_elements(std::vector<std::array<index_t, N>>& elements,
                       std::vector<index_t>& refs, bool& seen) {
    if (seen) return fail_here("section given twice");
    seen = true;
    long long count = 0;
    if (Status s = read_count(count); !s) return s;
    reserve_for(elements, count, N + 1);
    reserve_for(refs, count, N + 1);
    // Checked here (with the line) when the vertices are known, which is
    // the usual order; otherwise after the whole file.
    const long long n_points = seen_vertices_ ? static_cast<long long>(mesh_.points.size()) : -1;
    for (long long i = 0; i < count; ++i) {
      std::array<index_t, N> e{};
      for (std::size_t k = 0; k < N; ++k) {
        const std::string_view t = tok_.next();
        long long v = 0;
        if (!parse_integer(t, v)) return bad_entry_token(t, i, count, "a vertex index");
        if (n_points >= 0 ? (v < 1 || v > n_points)
                          : (v < 1 || v > std::numeric_limits<index_t>::max()))
          return fail_here("entry " + std::to_string(i + 1) + ": vertex index " +
                           std::to_string(v) + " out of range 1.." +
                           (n_points >= 0 ? std::to_string(n_points) : std::string("2^31-1")));
        e[k] = static_cast<index_t>(v - 1);  // Medit counts from 1
      }
      index_t ref = 0;
      if (Status s = read_ref(i, count, ref); !s) return s;
      elements.push_back(e);
      refs.push_back(ref);
    }
    return Status::success();
  }

  /// Sections we do not use: skip their data tokens up to the next keyword,
  /// which needs no table of per-entry sizes.
  void skip_section() {
    while (is_data_token(tok_.peek())) tok_.next();
  }

  template <std::size_t N>
  Status check_indices(const char* name, const std::vector<std::array<index_t, N>>& elements) {
    const auto n = static_cast<index_t>(mesh_.points.size());
    for (std::size_t i = 0; i < elements.size(); ++i)
      for (index_t v : elements[i])
        if (v >= n)
          return fail(std::string("section ") + name + ": entry " + std::to_string(i + 1) +
                      ": vertex index " + std::to_string(v + 1) + " out of range 1.." +
                      std::to_string(n));
    return Status::success();
  }

  const std::string& path_;
  Tokenizer tok_;
  MeditMesh& mesh_;
  std::string section_;
  bool seen_vertices_ = false;
  bool seen_tets_ = false;
  bool seen_triangles_ = false;
};

}  // namespace

Status read_medit_mesh(const std::string& path, MeditMesh& mesh) {
  mesh = MeditMesh{};
  std::error_code ec;
  if (!std::filesystem::exists(path, ec))
    return Status::failure("cannot open '" + path + "': no such file");
  if (!std::filesystem::is_regular_file(path, ec))
    return Status::failure("cannot open '" + path + "': not a regular file");
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) return Status::failure("cannot open '" + path + "': " + ec.message());

  std::ifstream in(path, std::ios::binary);
  if (!in) return Status::failure("cannot open '" + path + "': " + std::strerror(errno));
  std::string text(static_cast<std::size_t>(size), '\0');
  if (!in.read(text.data(), static_cast<std::streamsize>(size)))
    return Status::failure("cannot read '" + path + "'");

  Status status = MeditReader(path, text, mesh).run();
  if (!status) mesh = MeditMesh{};
  return status;
}

}  // namespace femorph
