// TetGen's tetrahedralize() on a triangle PLC (see tetgen_plc.h).
#include "adapt/tetgen_plc.h"

#include "geometry/predicates.h"

#include <tetgen.h>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <utility>

#if defined(__unix__) || defined(__APPLE__)
#include <poll.h>
#include <sys/resource.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>
#endif
#if defined(__linux__)
#include <sys/prctl.h>
#endif

namespace femorph {
namespace internal {

namespace {

/// TetGen's exit codes (terminatetetgen), as words.
const char* tetgen_error(int code) {
  switch (code) {
    case 1: return "out of memory";
    case 2: return "internal error";
    case 3: return "self-intersecting facets";
    case 4: return "a very small input feature";
    case 5: return "two very close facets";
    case 10: return "input error";
    default: return "unknown error";
  }
}

/// Runs tetrahedralize() and reads its points and tets; `code` is TetGen's
/// error code (0: none, -1: another exception).
void run_tetgen(std::string& switches, tetgenio& in, int& code, std::vector<Vec3>& points, std::vector<Tet>& tets) {
  tetgenio out;
  code = 0;
  // Built with TETLIBRARY, TetGen throws its exit code instead of exiting.
  try {
    tetrahedralize(&switches[0], &in, &out);
  } catch (int c) {
    code = c == 0 ? -1 : c;
  } catch (...) {
    code = -1;
  }
  if (code != 0) return;
  if (out.numberofcorners != 4) {
    code = -1;
    return;
  }
  points.resize(static_cast<std::size_t>(out.numberofpoints));
  for (int i = 0; i < out.numberofpoints; ++i)
    points[i] = Vec3(out.pointlist[3 * i], out.pointlist[3 * i + 1], out.pointlist[3 * i + 2]);
  tets.resize(static_cast<std::size_t>(out.numberoftetrahedra));
  for (int t = 0; t < out.numberoftetrahedra; ++t)
    for (int k = 0; k < 4; ++k) tets[t][k] = out.tetrahedronlist[4 * t + k];
}

#if defined(__unix__) || defined(__APPLE__)
bool write_all(int fd, const void* data, std::size_t n) {
  const char* p = static_cast<const char*>(data);
  while (n > 0) {
    const ssize_t w = ::write(fd, p, n);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) return false;
    p += w;
    n -= static_cast<std::size_t>(w);
  }
  return true;
}
#endif

/// TetGen 1.5.0 frees its memory when it stops on an error and then again
/// in its destructor while the exception unwinds: any TetGen error (a
/// self-intersecting PLC, a tiny feature) would crash the process. So it
/// runs in a forked child that sends its result through a pipe; a crash
/// there is a failure here.
Status run_isolated(std::string& switches, tetgenio& in, int& code, std::vector<Vec3>& points,
                    std::vector<Tet>& tets, std::string& saying) {
#if defined(__unix__) || defined(__APPLE__)
  // fds: the result; text: the child's stdout, where TetGen says why it
  // stopped.
  int fds[2], text[2];
  if (::pipe(fds) != 0) return Status::failure("TetGen: could not open a pipe");
  if (::pipe(text) != 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    return Status::failure("TetGen: could not open a pipe");
  }
  std::fflush(nullptr);  // the child must not write the parent's buffers again
  const pid_t pid = ::fork();
  if (pid < 0) {
    for (const int fd : {fds[0], fds[1], text[0], text[1]}) ::close(fd);
    return Status::failure("TetGen: could not start its process");
  }
  if (pid == 0) {
    // Child: message = code, #points, #tets, points, tets.
    ::close(fds[0]);
    ::close(text[0]);
    // TetGen's crash after an error would dump the whole caller's memory.
    const rlimit no_core{0, 0};
    ::setrlimit(RLIMIT_CORE, &no_core);
#if defined(__linux__)
    ::prctl(PR_SET_DUMPABLE, 0, 0, 0, 0);
#endif
    ::dup2(text[1], STDOUT_FILENO);
    std::setvbuf(stdout, nullptr, _IONBF, 0);  // kept if it crashes
    run_tetgen(switches, in, code, points, tets);
    const std::int64_t head[3] = {code, static_cast<std::int64_t>(points.size()), static_cast<std::int64_t>(tets.size())};
    const bool ok = write_all(fds[1], head, sizeof head) &&
                    write_all(fds[1], points.data(), points.size() * sizeof(Vec3)) &&
                    write_all(fds[1], tets.data(), tets.size() * sizeof(Tet));
    ::_exit(ok ? 0 : 1);
  }
  ::close(fds[1]);
  ::close(text[1]);
  // Both pipes read as data comes, so that neither fills and blocks the child.
  std::vector<char> message, said;
  char buffer[1 << 16];
  pollfd polls[2] = {{fds[0], POLLIN, 0}, {text[0], POLLIN, 0}};
  std::vector<char>* sink[2] = {&message, &said};
  int open_pipes = 2;
  while (open_pipes > 0) {
    if (::poll(polls, 2, -1) < 0) {
      if (errno == EINTR) continue;
      break;
    }
    for (int k = 0; k < 2; ++k) {
      if (polls[k].fd < 0 || polls[k].revents == 0) continue;
      const ssize_t r = ::read(polls[k].fd, buffer, sizeof buffer);
      if (r < 0 && errno == EINTR) continue;
      if (r <= 0) {
        ::close(polls[k].fd);
        polls[k].fd = -1;
        --open_pipes;
        continue;
      }
      sink[k]->insert(sink[k]->end(), buffer, buffer + r);
    }
  }
  for (const pollfd& p : polls)
    if (p.fd >= 0) ::close(p.fd);
  // TetGen's words without its progress lines ("...", "seconds"), on one
  // line: on an error, why it stopped.
  std::string why;
  std::size_t begin = 0;
  while (begin < said.size()) {
    std::size_t end = begin;
    while (end < said.size() && said[end] != '\n') ++end;
    std::string line(said.begin() + static_cast<std::ptrdiff_t>(begin), said.begin() + static_cast<std::ptrdiff_t>(end));
    begin = end + 1;
    while (!line.empty() && (line.back() == ' ' || line.back() == '\r')) line.pop_back();
    const std::size_t first = line.find_first_not_of(' ');
    if (first == std::string::npos) continue;
    line = line.substr(first);
    if (line.find("seconds") != std::string::npos ||
        (line.size() >= 3 && line.compare(line.size() - 3, 3, "...") == 0))
      continue;
    why += (why.empty() ? "" : " ") + line;
  }
  if (why.size() > 300) why = why.substr(0, 300) + "...";
  saying = why.empty() ? "" : ": TetGen says \"" + why + "\"";
  int wstatus = 0;
  while (::waitpid(pid, &wstatus, 0) < 0 && errno == EINTR) {
  }
  if (WIFSIGNALED(wstatus))
    return Status::failure("TetGen stopped (signal " + std::to_string(WTERMSIG(wstatus)) + ")" + saying);
  if (!WIFEXITED(wstatus) || WEXITSTATUS(wstatus) != 0)
    return Status::failure("TetGen's process stopped with status " + std::to_string(WEXITSTATUS(wstatus)) + saying);
  std::int64_t head[3];
  if (message.size() < sizeof head) return Status::failure("TetGen's process sent no result");
  std::memcpy(head, message.data(), sizeof head);
  const std::size_t np = static_cast<std::size_t>(head[1]), nt = static_cast<std::size_t>(head[2]);
  if (head[1] < 0 || head[2] < 0 || message.size() != sizeof head + np * sizeof(Vec3) + nt * sizeof(Tet))
    return Status::failure("TetGen's process sent a truncated result");
  code = static_cast<int>(head[0]);
  points.resize(np);
  tets.resize(nt);
  std::memcpy(static_cast<void*>(points.data()), message.data() + sizeof head, np * sizeof(Vec3));
  std::memcpy(static_cast<void*>(tets.data()), message.data() + sizeof head + np * sizeof(Vec3), nt * sizeof(Tet));
  return Status::success();
#else
  saying.clear();
  run_tetgen(switches, in, code, points, tets);
  return Status::success();
#endif
}

}  // namespace

Status tetgen_plc(const std::vector<Vec3>& points, const std::vector<std::array<index_t, 3>>& facets,
                  const std::vector<Vec3>& holes, const char* switches, std::vector<Vec3>& out_points,
                  std::vector<Tet>& out_tets) {
  out_points.clear();
  out_tets.clear();
  // tetgenio's destructor frees these arrays (new[]).
  tetgenio in;
  in.firstnumber = 0;
  in.numberofpoints = static_cast<int>(points.size());
  in.pointlist = new REAL[3 * points.size()];
  for (std::size_t i = 0; i < points.size(); ++i)
    for (int a = 0; a < 3; ++a) in.pointlist[3 * i + a] = points[i][a];
  in.numberoffacets = static_cast<int>(facets.size());
  in.facetlist = new tetgenio::facet[facets.size()];
  for (std::size_t f = 0; f < facets.size(); ++f) {
    tetgenio::facet& F = in.facetlist[f];
    tetgenio::init(&F);
    F.numberofpolygons = 1;
    F.polygonlist = new tetgenio::polygon[1];
    tetgenio::init(&F.polygonlist[0]);
    F.polygonlist[0].numberofvertices = 3;
    F.polygonlist[0].vertexlist = new int[3];
    for (int k = 0; k < 3; ++k) F.polygonlist[0].vertexlist[k] = facets[f][k];
  }
  in.numberofholes = static_cast<int>(holes.size());
  if (!holes.empty()) {
    in.holelist = new REAL[3 * holes.size()];
    for (std::size_t h = 0; h < holes.size(); ++h)
      for (int a = 0; a < 3; ++a) in.holelist[3 * h + a] = holes[h][a];
  }
  // tetrahedralize() takes a non-const string.
  std::string sw(switches);
  int code = 0;
  std::string saying;
  if (const Status s = run_isolated(sw, in, code, out_points, out_tets, saying); !s) return s;
  if (code != 0)
    return Status::failure(std::string("TetGen failed: ") + tetgen_error(code) + " (code " + std::to_string(code) +
                           ")" + saying);
  if (out_points.size() < points.size()) return Status::failure("TetGen returned an unexpected mesh");
  // Its first points are the input's (it keeps the order and, without -J,
  // every point): the callers map the output by this.
  for (std::size_t i = 0; i < points.size(); ++i)
    if (out_points[i] != points[i]) return Status::failure("TetGen moved or renumbered an input point");
  for (Tet& T : out_tets) {
    for (const index_t v : T)
      if (v < 0 || v >= static_cast<index_t>(out_points.size()))
        return Status::failure("TetGen returned a tet with a bad id");
    const int sign = orient3d_sign(out_points[T[0]], out_points[T[1]], out_points[T[2]], out_points[T[3]]);
    if (sign == 0) return Status::failure("TetGen returned a flat tet");
    if (sign < 0) std::swap(T[0], T[1]);
  }
  return Status::success();
}

}  // namespace internal
}  // namespace femorph
