// read_mesh / read_mesh_from_memory (locus/mesh_io.hpp): load a whole file into
// memory and hand it to the reader its extension names.
//
// The whole file is read with one read() loop: the readers then walk a buffer
// with pointers, which is what makes a 1M-vertex binary PLY load in tens of
// milliseconds (no iostream, no per-token allocation). Refusals (missing file,
// a directory, unknown extension, file bigger than ReadOptions::max_bytes) are
// locus::Error naming the file. Extensions other than .obj, .off and .ply go
// to assimp (read_assimp.cpp) when it reads them.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>
#include <vector>

#include "locus/io/readers.hpp"
#include "locus/io/file_extension.hpp"
#include "locus/error.hpp"
#include "locus/mesh_io.hpp"

namespace locus {
namespace {

using io::lower_extension;

bool own_format(const std::string& ext) { return ext == "obj" || ext == "off" || ext == "ply"; }

const char* kKnownFormats = "expected .obj, .off, .ply or a format assimp reads: .gltf, .glb, .fbx, .dae, .stl, .3mf, "
                            ".3ds, .x, ...";

// `dir`: the folder of the file read, where a .gltf's external buffers may
// be ("" for a buffer from memory).
Mesh dispatch(std::string_view data, const std::string& format, const std::string& name, const std::string& dir,
              const ReadOptions& opt, MeshAttributes* attributes) {
  if (data.empty()) fail(ErrorCode::BadInput, name + ": the file is empty");
  if (attributes) *attributes = {};
  if (format == "obj") return io::read_obj(data, name, opt, attributes);
  if (format == "off") return io::read_off(data, name, opt, attributes);
  if (format == "ply") return io::read_ply(data, name, opt, attributes);
  if (io::assimp_reads_extension(format)) return io::read_assimp(data, format, name, dir, opt, attributes);
  fail(ErrorCode::BadInput, name + ": unknown mesh format '" + format + "' (" + kKnownFormats + ")");
}

std::string folder_of(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  if (slash == std::string::npos) return ".";
  return slash == 0 ? "/" : path.substr(0, slash);
}

// Closes the descriptor on every exit path, including exceptions.
struct Fd {
  int fd;
  ~Fd() {
    if (fd >= 0) ::close(fd);
  }
};

}  // namespace

Mesh read_mesh(const std::string& path, const ReadOptions& opt) { return read_mesh(path, opt, nullptr); }

Mesh read_mesh(const std::string& path, const ReadOptions& opt, MeshAttributes* attributes) {
  const std::string ext = lower_extension(path);
  if (!own_format(ext) && !io::assimp_reads_extension(ext))
    fail(ErrorCode::BadInput, path + ": unknown mesh file extension '" + ext + "' (" + kKnownFormats + ")");

  // O_NONBLOCK: opening a FIFO named like a mesh must not wait for a writer;
  // the S_ISREG check below then refuses it. Reads of regular files ignore it.
  Fd f{::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK)};
  if (f.fd < 0) fail(ErrorCode::BadInput, path + ": cannot open: " + std::strerror(errno));
  struct stat st {};
  if (::fstat(f.fd, &st) != 0) fail(ErrorCode::BadInput, path + ": cannot stat: " + std::strerror(errno));
  if (S_ISDIR(st.st_mode)) fail(ErrorCode::BadInput, path + ": is a directory, not a mesh file");
  if (!S_ISREG(st.st_mode)) fail(ErrorCode::BadInput, path + ": is not a regular file");
  const uint64_t size = static_cast<uint64_t>(st.st_size);
  if (size > opt.max_bytes)
    fail(ErrorCode::ResourceLimit, path + ": the file has " + std::to_string(size) +
                                       " bytes, more than the limit of " + std::to_string(opt.max_bytes) +
                                       " bytes (ReadOptions::max_bytes)");

  std::vector<char> buf(size);
  size_t got = 0;
  while (got < size) {
    const ssize_t r = ::read(f.fd, buf.data() + got, size - got);
    if (r < 0 && errno == EINTR) continue;
    if (r < 0) fail(ErrorCode::BadInput, path + ": read error: " + std::strerror(errno));
    if (r == 0) break;  // the file shrank while we read it: parse what is there
    got += static_cast<size_t>(r);
  }
  return dispatch(std::string_view(buf.data(), got), ext, path, folder_of(path), opt, attributes);
}

Mesh read_mesh_from_memory(const char* data, size_t size, const std::string& format, const std::string& name,
                           const ReadOptions& opt, MeshAttributes* attributes) {
  std::string fmt = format;
  for (char& c : fmt)
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  if (!fmt.empty() && fmt[0] == '.') fmt.erase(0, 1);
  if (data == nullptr && size != 0) fail(ErrorCode::BadUsage, name + ": null buffer with nonzero size");
  return dispatch(std::string_view(data ? data : "", data ? size : 0), fmt, name, "", opt, attributes);
}

bool is_readable_mesh_extension(const std::string& ext) { return own_format(ext) || io::assimp_reads_extension(ext); }

}  // namespace locus
