// Reading OFF / OBJ triangle surfaces (read_surface, mesh.hpp; the checks in mesh_check.cpp). The
// reader is strict and must not
// crash or hang on arbitrary bytes (it is fuzzed): every count is checked against the file
// size before anything is reserved, and every token is parsed with std::from_chars.
#include "core/mesh_internal.hpp"

#include "core/geometry.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <string_view>
#include <system_error>

namespace harness {
namespace {

using mesh_detail::analyze;
using mesh_detail::Labels;

constexpr long long kMaxCount = 50'000'000;              // vertices or faces
constexpr std::uintmax_t kMaxFileBytes = 2'000'000'000;  // keeps line numbers in an int
constexpr double kMaxCoordinate = 1e12;                  // m; beyond this volumes overflow

template <class C>
int isize(const C& c) {
  return static_cast<int>(c.size());
}

// ---- tokenising --------------------------------------------------------------------------

struct Token {
  std::string_view text;
  int col;  // 1-based byte column
};

// Yields the lines that hold tokens; '#' starts a comment; \n, \r\n and lone \r end lines.
class LineReader {
 public:
  explicit LineReader(std::string_view buf) : buf_(buf) {}
  bool next(std::vector<Token>& tokens) {
    tokens.clear();
    while (pos_ < buf_.size()) {
      ++line_;
      const std::size_t start = pos_;
      std::size_t end = start;
      while (end < buf_.size() && buf_[end] != '\n' && buf_[end] != '\r') ++end;
      pos_ = end;
      if (pos_ < buf_.size()) {
        if (buf_[pos_] == '\r' && pos_ + 1 < buf_.size() && buf_[pos_ + 1] == '\n') ++pos_;
        ++pos_;
      }
      std::size_t i = start;
      while (i < end && buf_[i] != '#') {
        if (is_space(buf_[i])) {
          ++i;
          continue;
        }
        std::size_t j = i;
        while (j < end && !is_space(buf_[j]) && buf_[j] != '#') ++j;
        tokens.push_back({buf_.substr(i, j - i), static_cast<int>(i - start) + 1});
        i = j;
      }
      if (!tokens.empty()) return true;
    }
    return false;
  }
  int line() const { return line_; }

 private:
  static bool is_space(char c) { return c == ' ' || c == '\t' || c == '\v' || c == '\f'; }
  std::string_view buf_;
  std::size_t pos_ = 0;
  int line_ = 0;
};

// A token quoted for a one-line message: printable ASCII only, at most 32 characters.
std::string quote(std::string_view s) {
  std::string out = "'";
  for (std::size_t i = 0; i < s.size() && i < 32; ++i) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    out += (c >= 32 && c < 127) ? static_cast<char>(c) : '?';
  }
  if (s.size() > 32) out += "...";
  return out + "'";
}

bool parse_int(std::string_view s, long long& out) {
  if (!s.empty() && s[0] == '+') s.remove_prefix(1);
  if (s.empty() || s[0] == '+') return false;
  const auto res = std::from_chars(s.data(), s.data() + s.size(), out);
  return res.ec == std::errc() && res.ptr == s.data() + s.size();
}

bool parse_double(std::string_view s, double& out) {
  if (!s.empty() && s[0] == '+') s.remove_prefix(1);
  if (s.empty() || s[0] == '+') return false;
  const auto res = std::from_chars(s.data(), s.data() + s.size(), out);
  return res.ec == std::errc() && res.ptr == s.data() + s.size();
}

// ---- raw surface and its validation -----------------------------------------------------

struct Corner {
  long long index;  // 0-based vertex index as resolved from the file; range checked later
  int col;
};
struct Polygon {
  int line, col;  // where the face record starts
  std::size_t first;
  int count;
};
struct RawSurface {
  Points V;
  std::vector<Corner> corners;
  std::vector<Polygon> polys;
  long long base = 0;  // the file numbers its vertices from this (OFF 0, OBJ 1)
};

class Parser {
 public:
  Parser(const std::string& path, std::string_view buf) : path_(path), reader_(buf) {}
  [[noreturn]] void fail(int col, const std::string& what) const {
    throw InputError(path_ + ":" + std::to_string(reader_.line()) + ":" + std::to_string(col),
                     what);
  }
  [[noreturn]] void fail(const Token& t, const std::string& what) const { fail(t.col, what); }
  double coordinate(const Token& t) const {
    double x = 0.0;
    if (!parse_double(t.text, x)) fail(t, "bad number " + quote(t.text));
    if (!std::isfinite(x)) fail(t, "non-finite coordinate " + quote(t.text));
    if (std::fabs(x) > kMaxCoordinate)
      fail(t, "coordinate " + quote(t.text) + " is absurdly large");
    return x;
  }
  // Extra values after a record (colours, normals): ignored, but they must be numbers.
  void trailing_numbers(std::size_t from) const {
    for (std::size_t i = from; i < tokens.size(); ++i) {
      double x = 0.0;
      if (!parse_double(tokens[i].text, x)) fail(tokens[i], "unexpected " + quote(tokens[i].text));
    }
  }
  bool next() { return reader_.next(tokens); }
  int line() const { return reader_.line(); }

  std::vector<Token> tokens;

 private:
  const std::string& path_;
  LineReader reader_;
};

// The OFF header (optional) and counts line: returns the vertex and face counts.
std::pair<long long, long long> read_off_counts(Parser& p, const std::string& path, std::size_t bytes) {
  if (!p.next()) throw InputError(path, "empty file (no data)");
  std::size_t first = 0;
  // Optional header: OFF, or a variant with colours / normals / texture coordinates whose
  // extra vertex values are skipped as trailing numbers.
  static const char* const headers[] = {"OFF",   "COFF",   "NOFF",   "CNOFF",
                                        "STOFF", "STCOFF", "STNOFF", "STCNOFF"};
  if (std::find(std::begin(headers), std::end(headers), p.tokens[0].text) != std::end(headers)) {
    if (p.tokens.size() > 1) {
      first = 1;  // counts on the header line
    } else if (!p.next()) {
      throw InputError(path, "file ends after the header");
    }
  } else {
    long long dummy = 0;
    if (!parse_int(p.tokens[0].text, dummy))
      p.fail(p.tokens[0], "expected an 'OFF' header or the counts line, got " + quote(p.tokens[0].text));
  }
  long long counts[3] = {0, 0, 0};
  const std::size_t n_counts = p.tokens.size() - first;
  if (n_counts < 2 || n_counts > 3) p.fail(p.tokens[first].col, "expected the counts line 'vertices faces [edges]'");
  for (std::size_t i = 0; i < n_counts; ++i) {
    const Token& t = p.tokens[first + i];
    if (!parse_int(t.text, counts[i])) p.fail(t, "bad count " + quote(t.text));
    if (counts[i] < 0) p.fail(t, "negative count " + quote(t.text));
    if (counts[i] > kMaxCount) p.fail(t, "absurd count " + quote(t.text) + " (limit 50 million)");
  }
  const long long nv = counts[0], nf = counts[1];
  // The shortest records are "0 0 0\n" and "3 0 1 2\n": larger counts cannot be in the file.
  if (nv * 6 + nf * 8 > static_cast<long long>(bytes) + 2)
    p.fail(p.tokens[first].col, "absurd counts: " + std::to_string(nv) + " vertices and " + std::to_string(nf) +
                                    " faces cannot fit in " + std::to_string(bytes) + " bytes");
  if (nv == 0) throw InputError(path, "no vertices");
  if (nf == 0) throw InputError(path, "no faces");
  return {nv, nf};
}

// One OFF face record "n i1 ... in"; n_tris counts the triangles of all faces so far.
void read_off_face(Parser& p, long long nv, long long& n_tris, RawSurface& raw) {
  const Token& t = p.tokens[0];
  long long n = 0;
  if (!parse_int(t.text, n)) p.fail(t, "bad vertex count " + quote(t.text) + " of a face");
  if (n < 3) p.fail(t, "a face needs at least 3 vertices, got " + quote(t.text));
  if (n > static_cast<long long>(p.tokens.size()) - 1)
    p.fail(t, "the face declares " + std::to_string(n) + " vertices but only " +
                  std::to_string(p.tokens.size() - 1) + " values follow");
  if (n > nv) p.fail(t, "the face has more vertices than the file (" + std::to_string(nv) + ")");
  n_tris += n - 2;
  if (n_tris > kMaxCount) p.fail(t, "absurd number of triangles (limit 50 million)");
  raw.polys.push_back({p.line(), t.col, raw.corners.size(), static_cast<int>(n)});
  for (long long k = 1; k <= n; ++k) {
    const Token& c = p.tokens[static_cast<std::size_t>(k)];
    long long idx = 0;
    if (!parse_int(c.text, idx)) p.fail(c, "bad vertex index " + quote(c.text));
    if (idx < 0 || idx >= nv) p.fail(c, "vertex index " + quote(c.text) + " out of range [0, " + std::to_string(nv) + ")");
    raw.corners.push_back({idx, c.col});
  }
  p.trailing_numbers(static_cast<std::size_t>(n) + 1);
}

void read_off(const std::string& path, std::string_view buf, RawSurface& raw) {
  Parser p(path, buf);
  const auto [nv, nf] = read_off_counts(p, path, buf.size());
  raw.base = 0;
  raw.V.reserve(static_cast<std::size_t>(nv));
  for (long long i = 0; i < nv; ++i) {
    if (!p.next())
      throw InputError(path + ":" + std::to_string(p.line()),
                       "file ends after " + std::to_string(i) + " of " + std::to_string(nv) + " vertices");
    if (p.tokens.size() < 3) p.fail(p.tokens[0], "expected a vertex 'x y z'");
    raw.V.emplace_back(p.coordinate(p.tokens[0]), p.coordinate(p.tokens[1]), p.coordinate(p.tokens[2]));
    p.trailing_numbers(3);
  }
  raw.polys.reserve(static_cast<std::size_t>(nf));
  long long n_tris = 0;
  for (long long i = 0; i < nf; ++i) {
    if (!p.next())
      throw InputError(path + ":" + std::to_string(p.line()),
                       "file ends after " + std::to_string(i) + " of " + std::to_string(nf) + " faces");
    read_off_face(p, nv, n_tris, raw);
  }
  if (p.next()) p.fail(p.tokens[0], "unexpected content after the last of " + std::to_string(nf) + " faces");
}

void read_obj(const std::string& path, std::string_view buf, RawSurface& raw) {
  Parser p(path, buf);
  // Statements that carry nothing for a triangle surface.
  static const char* const ignored[] = {
      "vn",        "vt",    "vp",       "g",        "o",    "s",      "usemtl", "mtllib",
      "l",         "p",     "cstype",   "deg",      "bmat", "step",   "curv",   "curv2",
      "surf",      "parm",  "trim",     "hole",     "scrv", "sp",     "end",    "con",
      "mg",        "bevel", "c_interp", "d_interp", "lod",  "usemap", "maplib", "shadow_obj",
      "trace_obj", "ctech", "stech",    "call",     "csh"};
  raw.base = 1;
  bool any = false;
  long long n_tris = 0;
  while (p.next()) {
    any = true;
    const Token& kw = p.tokens[0];
    if (kw.text == "v") {
      if (p.tokens.size() < 4) p.fail(kw, "expected a vertex 'v x y z [w]'");
      if (p.tokens.size() > 8) p.fail(p.tokens[8], "too many values for a vertex");
      if (static_cast<long long>(raw.V.size()) >= kMaxCount)
        p.fail(kw, "absurd number of vertices (limit 50 million)");
      raw.V.emplace_back(p.coordinate(p.tokens[1]), p.coordinate(p.tokens[2]),
                         p.coordinate(p.tokens[3]));
      p.trailing_numbers(4);  // w, or vertex colours
    } else if (kw.text == "f" || kw.text == "fo") {
      const std::size_t n = p.tokens.size() - 1;
      if (n < 3) p.fail(kw, "a face needs at least 3 vertices, got " + std::to_string(n));
      n_tris += static_cast<long long>(n) - 2;
      if (n_tris > kMaxCount) p.fail(kw, "absurd number of faces (limit 50 million)");
      raw.polys.push_back({p.line(), kw.col, raw.corners.size(), static_cast<int>(n)});
      for (std::size_t k = 1; k <= n; ++k) {
        const Token& c = p.tokens[k];
        // v, v/vt, v/vt/vn or v//vn: the texture and normal references are checked, not used.
        std::string_view parts[3];
        std::size_t n_parts = 0;
        std::size_t start = 0;
        for (std::size_t i = 0; i <= c.text.size(); ++i) {
          if (i == c.text.size() || c.text[i] == '/') {
            if (n_parts == 3) p.fail(c, "bad face vertex " + quote(c.text));
            parts[n_parts++] = c.text.substr(start, i - start);
            start = i + 1;
          }
        }
        long long ref[3] = {0, 0, 0};
        for (std::size_t i = 0; i < n_parts; ++i) {
          if (i == 1 && n_parts == 3 && parts[i].empty()) continue;  // v//vn
          if (!parse_int(parts[i], ref[i]) || ref[i] == 0)
            p.fail(c, "bad face vertex " + quote(c.text));
        }
        long long idx = ref[0] > 0 ? ref[0] - 1 : static_cast<long long>(raw.V.size()) + ref[0];
        if (idx < 0)
          p.fail(c, "relative vertex index " + quote(parts[0]) + " refers before the first vertex");
        raw.corners.push_back({idx, c.col});
      }
    } else if (std::find(std::begin(ignored), std::end(ignored), kw.text) == std::end(ignored)) {
      p.fail(kw, "unknown OBJ statement " + quote(kw.text));
    }
  }
  if (!any) throw InputError(path, "empty file (no data)");
  if (raw.V.empty()) throw InputError(path, "no vertices");
  if (raw.polys.empty()) throw InputError(path, "no faces");
}

// Range and degeneracy checks, fan triangulation, dropping unused vertices, topology and
// orientation.
SurfaceMesh finish_surface(const std::string& path, RawSurface& raw) {
  auto at = [&](int line, int col) {
    return path + ":" + std::to_string(line) + ":" + std::to_string(col);
  };
  const long long nv = static_cast<long long>(raw.V.size());
  std::vector<int> seen(raw.V.size(), -1);  // polygon that last used each vertex
  std::vector<Tri> F;
  std::vector<int> face_line;
  for (std::size_t pi = 0; pi < raw.polys.size(); ++pi) {
    const Polygon& poly = raw.polys[pi];
    for (int k = 0; k < poly.count; ++k) {
      const Corner& c = raw.corners[poly.first + k];
      if (c.index < 0 || c.index >= nv)
        throw InputError(at(poly.line, c.col),
                         "vertex index " + std::to_string(c.index + raw.base) +
                             " out of range (the file has " + std::to_string(nv) + " vertices)");
      if (seen[c.index] == static_cast<int>(pi))
        throw InputError(
            at(poly.line, c.col),
            "degenerate face: vertex " + std::to_string(c.index + raw.base) + " appears twice");
      seen[c.index] = static_cast<int>(pi);
    }
    const int i0 = static_cast<int>(raw.corners[poly.first].index);
    for (int k = 1; k + 1 < poly.count; ++k) {
      const int i1 = static_cast<int>(raw.corners[poly.first + k].index);
      const int i2 = static_cast<int>(raw.corners[poly.first + k + 1].index);
      const Vec3 &a = raw.V[i0], &b = raw.V[i1], &c = raw.V[i2];
      const double longest2 =
          std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
      // Relative test: the sine of the largest angle's complement is below 1e-12.
      if (!((b - a).cross(c - a).norm() > 1e-12 * longest2))
        throw InputError(at(poly.line, poly.col), "zero-area triangle (vertices " +
                                                      std::to_string(i0 + raw.base) + ", " +
                                                      std::to_string(i1 + raw.base) + ", " +
                                                      std::to_string(i2 + raw.base) + ")");
      F.push_back({i0, i1, i2});
      face_line.push_back(poly.line);
    }
  }
  raw.corners.clear();
  raw.corners.shrink_to_fit();

  // Keep referenced vertices in file order.
  std::vector<int> renum(raw.V.size(), -1);
  for (const Tri& t : F)
    for (int v : t) renum[v] = 0;
  SurfaceMesh mesh;
  std::vector<long long> label;
  for (std::size_t v = 0; v < raw.V.size(); ++v)
    if (renum[v] == 0) {
      renum[v] = isize(mesh.V);
      mesh.V.push_back(raw.V[v]);
      label.push_back(static_cast<long long>(v) + raw.base);
    }
  for (Tri& t : F)
    for (int& v : t) v = renum[v];
  mesh.F = std::move(F);

  Labels lab{&label, &face_line};
  const SurfaceReport rep = analyze(mesh.V, mesh.F, lab);
  if (!rep.closed || !rep.manifold || !rep.oriented) throw InputError(path, rep.problem);

  Vec3 lo = mesh.V[0], hi = mesh.V[0];
  for (const Vec3& v : mesh.V) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  const double diag = (hi - lo).norm();
  double vol = rep.signed_volume;
  if (!(std::fabs(vol) > 1e-12 * diag * diag * diag))
    throw InputError(path, "the surface encloses no volume");
  if (vol < 0.0)
    for (Tri& t : mesh.F) std::swap(t[1], t[2]);
  return mesh;
}

}  // namespace

SurfaceMesh read_surface(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path fp(path);
  std::string ext = fp.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext != ".off" && ext != ".obj")
    throw InputError(path, "unknown surface format " + quote(ext) + " (expected .off or .obj)");
  const fs::file_status st = fs::status(fp, ec);
  if (!fs::exists(st)) throw InputError(path, "no such file");
  if (ec) throw InputError(path, "cannot access the file: " + ec.message());
  if (!fs::is_regular_file(st)) throw InputError(path, "not a regular file");
  const std::uintmax_t size = fs::file_size(fp, ec);
  if (ec) throw InputError(path, "cannot read the file size: " + ec.message());
  if (size > kMaxFileBytes) throw InputError(path, "file too large (limit 2 GB)");

  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot open the file for reading");
  std::string buf(static_cast<std::size_t>(size), '\0');
  if (size > 0 && !in.read(&buf[0], static_cast<std::streamsize>(size)))
    throw InputError(path, "cannot read the file");
  return read_surface_text(buf, path, ext == ".obj");
}

SurfaceMesh read_surface_text(const std::string& text, const std::string& name, bool obj) {
  if (text.size() > kMaxFileBytes) throw InputError(name, "file too large (limit 2 GB)");
  if (text.empty()) throw InputError(name, "empty file");
  RawSurface raw;
  if (obj)
    read_obj(name, text, raw);
  else
    read_off(name, text, raw);
  return finish_surface(name, raw);
}

}  // namespace harness
