// Asset formats through assimp (io/include/locus/io/readers.hpp): glTF 2.0
// (.gltf, .glb), FBX, Collada, STL, 3MF, 3DS, DirectX .x and every other
// format the linked assimp reads, except OBJ, OFF and PLY, which locus's own
// readers handle (faster, and hardened by the fuzzers).
//
// Hostile files (DESIGN.md "Input is hostile"): assimp parses the bytes
// read_mesh already loaded under ReadOptions::max_bytes; its refusals (a
// null scene with an error string, or an exception) become locus::Error
// BadInput naming the file and carrying assimp's words. The scene is checked
// by assimp's ValidateDataStructure step and again while flattening (index
// ranges, finite positions, sizes before allocating).
//
// Which files assimp may open: assimp asks its IOSystem for every file it
// reads. Ours serves the buffer under the file's own name and nothing else,
// except for a text glTF read from disk, whose external buffers (.bin) are
// part of the asset by the glTF specification: those are read from the
// .gltf's own folder or below (relative names without "..", regular files
// within max_bytes). Textures and material libraries are never needed for
// geometry, so no other format may reach another file.
//
// Silence: assimp logs only through its DefaultLogger, which is a null
// logger unless a host creates one; locus never does, so nothing reaches the
// host's stdout or stderr.
#include <assimp/IOStream.hpp>
#include <assimp/IOSystem.hpp>
#include <assimp/Importer.hpp>
#include <assimp/config.h>
#include <assimp/importerdesc.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <new>
#include <string>
#include <vector>

#include "locus/error.hpp"
#include "locus/io/flatten_scene.hpp"
#include "locus/io/readers.hpp"

namespace locus::io {
namespace {

// A read-only stream over bytes (borrowed for the main file, owned for a sibling).
class BufferStream final : public Assimp::IOStream {
 public:
  BufferStream(const uint8_t* data, size_t size) : data_(data), size_(size) {}
  explicit BufferStream(std::vector<uint8_t> owned)
      : owned_(std::move(owned)), data_(owned_.data()), size_(owned_.size()) {}
  size_t Read(void* out, size_t size, size_t count) override {
    if (size == 0 || count == 0 || !out) return 0;
    const size_t n = std::min(count, (size_ - pos_) / size);
    if (n) std::memcpy(out, data_ + pos_, n * size);
    pos_ += n * size;
    return n;
  }
  size_t Write(const void*, size_t, size_t) override { return 0; }
  aiReturn Seek(size_t offset, aiOrigin origin) override {
    size_t to;
    if (origin == aiOrigin_SET) to = offset;
    else if (origin == aiOrigin_CUR) to = offset > size_ - pos_ ? size_ + 1 : pos_ + offset;
    else if (origin == aiOrigin_END) to = offset > size_ ? size_ + 1 : size_ - offset;
    else return AI_FAILURE;
    if (to > size_) return AI_FAILURE;
    pos_ = to;
    return AI_SUCCESS;
  }
  size_t Tell() const override { return pos_; }
  size_t FileSize() const override { return size_; }
  void Flush() override {}

 private:
  std::vector<uint8_t> owned_;
  const uint8_t* data_;
  size_t size_;
  size_t pos_ = 0;
};

// The only files assimp may open: `main` (the buffer) and, when `dir` is not
// empty, regular files below `dir` named relatively.
class AssetFiles final : public Assimp::IOSystem {
 public:
  AssetFiles(std::string main, std::string_view data, std::string dir, uint64_t max_bytes)
      : main_(std::move(main)), data_(data), dir_(std::move(dir)), max_bytes_(max_bytes) {}

  bool Exists(const char* file) const override {
    if (!file) return false;
    if (main_ == file) return true;
    std::string p;
    struct stat st {};
    return sibling(file, p) && ::stat(p.c_str(), &st) == 0 && S_ISREG(st.st_mode);
  }
  char getOsSeparator() const override { return '/'; }
  Assimp::IOStream* Open(const char* file, const char* mode) override {
    if (!file || (mode && mode[0] != 'r')) return nullptr;  // never written to
    if (main_ == file) return new BufferStream(reinterpret_cast<const uint8_t*>(data_.data()), data_.size());
    std::string p;
    if (!sibling(file, p)) return nullptr;
    std::vector<uint8_t> bytes;
    if (!read_regular(p, bytes)) return nullptr;
    return new BufferStream(std::move(bytes));
  }
  void Close(Assimp::IOStream* s) override { delete s; }

 private:
  // A relative name below dir_: no absolute path, no "..", no URI scheme or drive.
  bool sibling(const char* file, std::string& path) const {
    if (dir_.empty()) return false;
    std::string f(file);
    std::replace(f.begin(), f.end(), '\\', '/');
    while (f.rfind("./", 0) == 0) f.erase(0, 2);
    if (f.empty() || f[0] == '/' || f.find(':') != std::string::npos) return false;
    size_t b = 0;
    while (b <= f.size()) {
      const size_t e = std::min(f.find('/', b), f.size());
      if (f.compare(b, e - b, "..") == 0 && e - b == 2) return false;
      b = e + 1;
    }
    path = dir_ + "/" + f;
    return true;
  }
  bool read_regular(const std::string& p, std::vector<uint8_t>& out) const {
    const int fd = ::open(p.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
    if (fd < 0) return false;
    struct stat st {};
    bool ok = ::fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && uint64_t(st.st_size) <= max_bytes_;
    if (ok) {
      out.resize(size_t(st.st_size));
      size_t got = 0;
      while (got < out.size()) {
        const ssize_t r = ::read(fd, out.data() + got, out.size() - got);
        if (r < 0 && errno == EINTR) continue;
        if (r <= 0) break;
        got += size_t(r);
      }
      out.resize(got);
    }
    ::close(fd);
    return ok;
  }

  std::string main_;
  std::string_view data_;
  std::string dir_;
  uint64_t max_bytes_;
};

// The name assimp sees for the buffer: the file's own name (so assimp's
// messages read naturally), ending in the format's extension (which picks
// the importer).
std::string main_name(const std::string& name, const std::string& format) {
  const size_t slash = name.find_last_of('/');
  std::string base = slash == std::string::npos ? name : name.substr(slash + 1);
  if (base.empty()) base = "asset";
  std::string lower = base;
  for (char& c : lower)
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  const std::string dot = "." + format;
  if (lower.size() <= dot.size() || lower.compare(lower.size() - dot.size(), dot.size(), dot) != 0) base += dot;
  return base;
}

}  // namespace

bool assimp_reads_extension(const std::string& ext) {
  if (ext.empty() || ext.find_first_of("*;. ") != std::string::npos) return false;
  Assimp::Importer importer;
  return importer.IsExtensionSupported(ext);
}

Mesh read_assimp(std::string_view data, const std::string& format, const std::string& name,
                 const std::string& sibling_dir, const ReadOptions& opt, MeshAttributes* attributes) {
  Assimp::Importer importer;
  // A .gltf is the only format whose geometry may live in other files.
  const std::string dir = format == "gltf" ? sibling_dir : std::string();
  const std::string main = main_name(name, format);
  importer.SetIOHandler(new AssetFiles(main, data, dir, opt.max_bytes));  // the importer owns it
  // Coordinates as the file writes them (no Y-up rotation of Collada files),
  // like OBJ, OFF and PLY; no dummy meshes drawn for skeletons.
  importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
  importer.SetPropertyBool(AI_CONFIG_IMPORT_NO_SKELETON_MESHES, true);
  const unsigned flags = aiProcess_Triangulate | aiProcess_ValidateDataStructure;

  const aiScene* scene = nullptr;
  std::string why;
  try {
    scene = importer.ReadFile(main, flags);
    if (!scene) why = importer.GetErrorString();
  } catch (const std::bad_alloc&) {
    fail(ErrorCode::ResourceLimit, name + ": assimp ran out of memory reading the file");
  } catch (const std::exception& e) {
    why = e.what();
  } catch (...) {
    why = "assimp failed with an unknown exception";
  }
  if (!scene) {
    if (why.empty()) why = "assimp could not read it";
    while (!why.empty() && (why.back() == '\n' || why.back() == ' ')) why.pop_back();
    fail(ErrorCode::BadInput, name + ": not a readable ." + format + " file: " + why);
  }

  AssetReport report;
  Mesh m = flatten_scene(*scene, name, opt, report);
  if (const aiImporterDesc* d = importer.GetImporterInfo(size_t(importer.GetImporterIndex(format.c_str()))))
    report.format = d->mName ? d->mName : "";
  if (attributes) {
    attributes->asset = true;
    attributes->asset_report = std::move(report);
  }
  return m;
}

}  // namespace locus::io
