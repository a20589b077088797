// Reading OFF / OBJ surfaces and checking their topology.
#include <atomic>
#include "tests/core/surface_checks.hpp"

#include <catch2/catch.hpp>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>
#include <string>

#include "core/mesh.hpp"

using namespace harness;
namespace fs = std::filesystem;

namespace {

// A fresh directory under the system temp directory, removed afterwards.
struct TempDir {
  fs::path dir;
  TempDir() {
    static std::atomic<int> counter{0};
    const auto stamp = std::chrono::steady_clock::now().time_since_epoch().count();
    dir = fs::temp_directory_path() /
          ("harness_test_mesh_" + std::to_string(stamp) + "_" + std::to_string(counter++));
    fs::create_directories(dir);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
  std::string write(const std::string& name, const std::string& text) const {
    const fs::path p = dir / name;
    std::ofstream(p, std::ios::binary) << text;
    return p.string();
  }
};

const char* kCubeOff =
    "OFF\n"
    "# a cube of side 2, quads\n"
    "8 6 12\n"
    "-1 -1 -1\n 1 -1 -1\n 1 1 -1\n -1 1 -1\n"
    "-1 -1 1\n 1 -1 1\n 1 1 1\n -1 1 1\n"
    "\n"
    "4 0 3 2 1\n"
    "4 4 5 6 7\n"
    "4 0 1 5 4 255 0 0\n"  // a colour after the indices
    "4 2 3 7 6\n"
    "4 1 2 6 5\n"
    "4 0 4 7 3\n";

const char* kCubeObj =
    "# cube\n"
    "mtllib cube.mtl\n"
    "o cube\n"
    "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\n"
    "v -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1 1.0\n"
    "vt 0 0\nvt 1 0\nvt 1 1\n"
    "vn 0 0 1\n"
    "g side\nusemtl red\ns off\n"
    "f 1 4 3 2\n"
    "f 5/1 6/2 7/3 8/1\n"
    "f 1/1/1 2/2/1 6/3/1 5/1/1\n"
    "f 3//1 4//1 8//1 7//1\n"
    "f -7 -6 -2 -3\n"  // 2 3 7 6, relative
    "f 1 5 8 4 # trailing comment\n";

// Octahedron with vertices on the axes (+x, -x, +y, -y, +z, -z), outward.
const char* kOctaVerts = "1 0 0\n-1 0 0\n0 1 0\n0 -1 0\n0 0 1\n0 0 -1\n";
const int kOctaFaces[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                              {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};

std::string octa_off(bool inward = false, int skip_face = -1) {
  std::string s = "OFF\n6 " + std::to_string(skip_face >= 0 ? 7 : 8) + " 0\n" + kOctaVerts;
  for (int f = 0; f < 8; ++f) {
    if (f == skip_face) continue;
    const auto& t = kOctaFaces[f];
    s += "3 " + std::to_string(t[0]) + " " + std::to_string(inward ? t[2] : t[1]) + " " +
         std::to_string(inward ? t[1] : t[2]) + "\n";
  }
  return s;
}

std::string octa_obj() {
  std::string s;
  for (const char* p = kOctaVerts; *p;) {
    const char* e = p;
    while (*e != '\n') ++e;
    s += "v " + std::string(p, e) + "\n";
    p = e + 1;
  }
  for (const auto& t : kOctaFaces)
    s += "f " + std::to_string(t[0] + 1) + " " + std::to_string(t[1] + 1) + " " +
         std::to_string(t[2] + 1) + "\n";
  return s;
}

SurfaceMesh octahedron() {
  SurfaceMesh m;
  m.V = {Vec3(1, 0, 0),  Vec3(-1, 0, 0), Vec3(0, 1, 0),
         Vec3(0, -1, 0), Vec3(0, 0, 1),  Vec3(0, 0, -1)};
  for (const auto& t : kOctaFaces) m.F.push_back({t[0], t[1], t[2]});
  return m;
}

SurfaceMesh tetrahedron(const Vec3& o, int base = 0) {
  SurfaceMesh m;
  m.V = {o, o + Vec3(1, 0, 0), o + Vec3(0, 1, 0), o + Vec3(0, 0, 1)};
  m.F = {{base + 0, base + 2, base + 1},
         {base + 0, base + 1, base + 3},
         {base + 0, base + 3, base + 2},
         {base + 1, base + 2, base + 3}};
  return m;
}

void require_good(const SurfaceMesh& m, double volume) {
  CHECK(harness::test::require_sphere_topology(m).signed_volume == Approx(volume));
}

// The message of the InputError thrown by read_surface(path), or "" when none is thrown.
std::string read_error(const std::string& path) {
  try {
    read_surface(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("check_surface accepts closed outward surfaces", "[mesh]") {
  require_good(octahedron(), 4.0 / 3.0);
  require_good(tetrahedron(Vec3(5, 6, 7)), 1.0 / 6.0);
  const SurfaceMesh m = octahedron();
  CHECK(signed_volume(m.V, m.F) == Approx(4.0 / 3.0));
}

TEST_CASE("check_surface reports problems", "[mesh]") {
  SECTION("inward orientation: negative volume") {
    SurfaceMesh m = octahedron();
    for (Tri& t : m.F) std::swap(t[1], t[2]);
    const SurfaceReport r = check_surface(m);
    CHECK(r.closed);
    CHECK(r.oriented);
    CHECK(r.signed_volume == Approx(-4.0 / 3.0));
    CHECK_FALSE(r.ok());
  }
  SECTION("one face flipped: inconsistent orientation") {
    SurfaceMesh m = octahedron();
    std::swap(m.F[3][1], m.F[3][2]);
    const SurfaceReport r = check_surface(m);
    CHECK(r.closed);
    CHECK_FALSE(r.oriented);
    CHECK_FALSE(r.ok());
    CHECK(r.problem.find("orientation") != std::string::npos);
  }
  SECTION("missing face: open") {
    SurfaceMesh m = octahedron();
    m.F.pop_back();
    const SurfaceReport r = check_surface(m);
    CHECK_FALSE(r.closed);
    CHECK_FALSE(r.manifold);
    CHECK(r.problem.find("not closed") != std::string::npos);
  }
  SECTION("two tetrahedra touching at a vertex: pinched") {
    // The second tetrahedron's apex is moved onto vertex 0 of the first; they touch there only.
    SurfaceMesh m = tetrahedron(Vec3(0, 0, 0));
    SurfaceMesh c = tetrahedron(Vec3(-1, -1, -1));
    c.V[3] = Vec3(0, 0, 0);
    m.V.insert(m.V.end(), c.V.begin(), c.V.begin() + 3);
    // Second tetrahedron over vertices 4, 5, 6 and the shared vertex 0.
    auto idx = [](int v) { return v == 3 ? 0 : v + 4; };
    for (const Tri& t : c.F) m.F.push_back({idx(t[0]), idx(t[1]), idx(t[2])});
    const SurfaceReport r = check_surface(m);
    CHECK(r.closed);
    CHECK(r.oriented);
    CHECK_FALSE(r.manifold);
    CHECK(r.components == 1);
    CHECK(r.problem.find("fans") != std::string::npos);
  }
  SECTION("two disjoint tetrahedra: two components, Euler 4") {
    SurfaceMesh m = tetrahedron(Vec3(0, 0, 0));
    const SurfaceMesh b = tetrahedron(Vec3(3, 0, 0), 4);
    m.V.insert(m.V.end(), b.V.begin(), b.V.end());
    m.F.insert(m.F.end(), b.F.begin(), b.F.end());
    const SurfaceReport r = check_surface(m);
    CHECK(r.ok());
    CHECK(r.components == 2);
    CHECK(r.euler == 4);
  }
  SECTION("unreferenced vertex") {
    SurfaceMesh m = octahedron();
    m.V.push_back(Vec3(5, 5, 5));
    const SurfaceReport r = check_surface(m);
    CHECK_FALSE(r.manifold);
    CHECK(r.problem.find("no face") != std::string::npos);
  }
  SECTION("index out of range and degenerate faces do not crash") {
    SurfaceMesh m = octahedron();
    m.F[0][1] = 17;
    CHECK_FALSE(check_surface(m).ok());
    CHECK(check_surface(m).problem.find("out of range") != std::string::npos);
    m.F[0] = {1, 1, 2};
    CHECK_FALSE(check_surface(m).ok());
    CHECK_FALSE(check_surface(SurfaceMesh{}).ok());
  }
}

TEST_CASE("read_surface reads a quad cube in OFF and OBJ", "[mesh]") {
  TempDir tmp;
  for (const std::string& path :
       {tmp.write("cube.off", kCubeOff), tmp.write("cube.OBJ", kCubeObj)}) {
    INFO(path);
    const SurfaceMesh m = read_surface(path);
    CHECK(m.V.size() == 8);
    CHECK(m.F.size() == 12);  // six quads, fan-triangulated
    require_good(m, 8.0);
  }
}

TEST_CASE("read_surface reads an octahedron in OFF and OBJ", "[mesh]") {
  TempDir tmp;
  const SurfaceMesh a = read_surface(tmp.write("octa.off", octa_off()));
  const SurfaceMesh b = read_surface(tmp.write("octa.obj", octa_obj()));
  require_good(a, 4.0 / 3.0);
  require_good(b, 4.0 / 3.0);
  CHECK(a.F == b.F);
  CHECK(a.F == octahedron().F);
  // No header, CRLF line ends, tabs.
  std::string crlf = octa_off();
  crlf = crlf.substr(4);  // drop "OFF\n"
  std::string out;
  for (char c : crlf)
    out += c == '\n' ? std::string("\r\n") : c == ' ' ? std::string("\t") : std::string(1, c);
  require_good(read_surface(tmp.write("octa_crlf.off", out)), 4.0 / 3.0);
}

TEST_CASE("read_surface flips an inward surface and drops unused vertices", "[mesh]") {
  TempDir tmp;
  const SurfaceMesh m = read_surface(tmp.write("inward.off", octa_off(true)));
  require_good(m, 4.0 / 3.0);
  CHECK(m.F == octahedron().F);
  // Unused vertices (first and last) are dropped and the rest renumbered: the faces refer to
  // the octahedron's vertices as 2..7.
  std::string faces;
  for (const auto& t : kOctaFaces)
    faces += "f " + std::to_string(t[0] + 2) + " " + std::to_string(t[1] + 2) + " " +
             std::to_string(t[2] + 2) + "\n";
  std::string verts = "v 9 9 9\n";
  for (const Vec3& v : octahedron().V)
    verts += "v " + std::to_string(v.x()) + " " + std::to_string(v.y()) + " " +
             std::to_string(v.z()) + "\n";
  verts += "v 8 8 8\n";
  const SurfaceMesh u = read_surface(tmp.write("unused.obj", verts + faces));
  CHECK(u.V.size() == 6);
  CHECK(u.F == octahedron().F);
  require_good(u, 4.0 / 3.0);
}

TEST_CASE("read_surface rejects bad input with the place of the problem", "[mesh]") {
  TempDir tmp;
  auto expect = [&](const std::string& name, const std::string& text, const std::string& where,
                    const std::string& what) {
    const std::string path = tmp.write(name, text);
    const std::string msg = read_error(path);
    INFO("message: " << msg);
    CHECK(msg.find(path + where) == 0);
    CHECK(msg.find(what) != std::string::npos);
  };

  SECTION("missing file") {
    const std::string path = (tmp.dir / "missing.off").string();
    const std::string msg = read_error(path);
    CHECK(msg.find(path) == 0);
    CHECK(msg.find("no such file") != std::string::npos);
  }
  SECTION("a directory, an unknown extension, an empty file") {
    fs::create_directories(tmp.dir / "dir.off");
    const std::string dir = (tmp.dir / "dir.off").string();
    CHECK(read_error(dir).find(dir + ": not a regular file") == 0);
    expect("a.stl", "solid\n", ":", "unknown surface format");
    expect("empty.off", "", ":", "empty");
    expect("comments.obj", "# nothing\n\n", ":", "empty");
  }
  SECTION("garbage") {
    std::string bytes;
    std::mt19937 rng(7);
    for (int i = 0; i < 2000; ++i) bytes += static_cast<char>(rng() & 0xff);
    for (const char* name : {"garbage.off", "garbage.obj"}) {
      const std::string path = tmp.write(name, bytes);
      const std::string msg = read_error(path);
      INFO(msg);
      CHECK(msg.find(path + ":") == 0);
    }
    expect("words.off", "OFF\nhello world\n", ":2:1:", "bad count 'hello'");
    expect("words.obj", "v 1 2 3\nvertex 1 2 3\n", ":2:1:", "unknown OBJ statement");
    expect("badnum.obj", "v 1 2 3x\n", ":1:7:", "bad number '3x'");
    expect("badref.obj", octa_obj() + "f 1/x 2 3\n", ":15:3:", "bad face vertex '1/x'");
    expect("zero.obj", octa_obj() + "f 0 2 3\n", ":15:3:", "bad face vertex '0'");
  }
  SECTION("not closed: a face missing") {
    expect("open.off", octa_off(false, 5), ":", "not closed");
    expect("open.off", octa_off(false, 5), ": ", "line");
  }
  SECTION("non-manifold edge: three faces") {
    // A tetrahedron with a fin on its edge (0, 1).
    const std::string off =
        "OFF\n5 5 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 -1 -1\n"
        "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n3 0 1 4\n";
    expect("fin.off", off, ": ", "shared by 3 faces");
  }
  SECTION("inconsistent orientation") {
    std::string off = octa_off();
    off.replace(off.find("3 0 2 4"), 7, "3 0 4 2");
    expect("flip.off", off, ": ", "orientation");
  }
  SECTION("index out of range") {
    std::string off = octa_off();
    off.replace(off.find("3 1 3 4"), 7, "3 1 3 6");
    expect("range.off", off, ":11:7:", "out of range");
    expect("range.obj", octa_obj() + "f 1 2 9\n", ":15:7:", "out of range");
    expect("relative.obj", "v 0 0 0\nf -1 -2 -3\n", ":2:6:", "before the first vertex");
  }
  SECTION("absurd counts") {
    expect("huge.off", "OFF\n100000000 1 0\n0 0 0\n", ":2:1:", "absurd count");
    expect("big.off", "OFF\n1000 1000 0\n0 0 0\n", ":2:1:", "cannot fit");
    expect("negative.off", "OFF\n-3 1 0\n", ":2:1:", "negative count");
    expect("short.off", "OFF\n6 2\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 1 1\n2 2 2\n3 0 1 2\n", ":9",
           "file ends after 1 of 2 faces");
    expect("long.off", octa_off() + "3 0 1 2\n", ":17:1:", "unexpected content");
    expect("nofaces.off", "OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n", ":", "no faces");
  }
  SECTION("NaN and infinite coordinates") {
    std::string off = octa_off();
    off.replace(off.find("0 0 -1"), 6, "0 0 nan");
    expect("nan.off", off, ":8:5:", "non-finite");
    expect("inf.obj", "v 0 0 0\nv inf 0 0\n", ":2:3:", "non-finite");
  }
  SECTION("degenerate faces") {
    std::string off = octa_off();
    off.replace(off.find("3 0 2 4"), 7, "3 0 2 2");
    expect("repeat.off", off, ":9:7:", "degenerate");
    expect("fewer.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n", ":6:1:", "at least 3");
    expect("fewer.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n", ":3:1:", "at least 3");
    // Collinear vertices: zero area.
    expect("flat.off",
           "OFF\n4 4 0\n0 0 0\n1 0 0\n2 0 0\n0 1 0\n3 0 1 2\n3 0 2 3\n3 1 0 3\n3 2 1 3\n",
           ":7:1:", "zero-area");
  }
}

TEST_CASE("read_surface never crashes on mutated files", "[mesh]") {
  // A light in-process fuzz: random byte edits of valid files either read or throw InputError.
  TempDir tmp;
  std::mt19937 rng(12345);
  const std::string seeds[] = {kCubeOff, kCubeObj, octa_off(), octa_obj()};
  const char alphabet[] = "0123456789 -+.#/\nOFFfv eE\r\tnan";
  for (int trial = 0; trial < 400; ++trial) {
    const bool off = trial % 2 == 0;
    std::string s = seeds[(trial % 2) + 2 * ((trial / 2) % 2)];
    const int edits = 1 + static_cast<int>(rng() % 4);
    for (int e = 0; e < edits && !s.empty(); ++e) {
      const std::size_t at = rng() % s.size();
      switch (rng() % 3) {
        case 0:
          s[at] = alphabet[rng() % (sizeof(alphabet) - 1)];
          break;
        case 1:
          s.erase(at, 1 + rng() % 3);
          break;
        default:
          s.insert(at, 1, alphabet[rng() % (sizeof(alphabet) - 1)]);
          break;
      }
    }
    const std::string path = tmp.write(off ? "fuzz.off" : "fuzz.obj", s);
    try {
      const SurfaceMesh m = read_surface(path);
      CHECK(check_surface(m).ok());
    } catch (const InputError& e) {
      CHECK(std::string(e.what()).find(path) == 0);
    }
  }
}
