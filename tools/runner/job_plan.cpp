// The items of a `locus run`: inputs expanded, named and split into shards.
// Stems are given before the --shard split, so every shard of a corpus names
// an input alike and --merge can combine their summaries.
#include "tools/runner/job_plan.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <set>
#include <system_error>
#include <utility>

#include "locus/mesh_io.hpp"

namespace locus::runner {
namespace {

namespace fs = std::filesystem;

// What read_mesh reads: OFF, OBJ, PLY and the asset formats assimp reads (glTF, FBX, ...).
bool is_mesh_file(const fs::path& p) {
  std::string e = p.extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return e.size() > 1 && is_readable_mesh_extension(e.substr(1));
}

// The files under a folder: directly inside it, or (recursive) at any depth.
// Meshes go to `files`, everything else to `ignored`; an unreadable entry sets ec.
void list_folder(const std::string& in, bool recursive, std::vector<std::string>& files,
                 std::vector<std::string>& ignored, std::error_code& ec) {
  auto take = [&](const fs::directory_entry& e) {
    std::error_code fec;
    if (e.is_directory(fec)) return;
    if (is_mesh_file(e.path())) files.push_back(e.path().string());
    else ignored.push_back(e.path().string());
  };
  if (recursive) {
    for (fs::recursive_directory_iterator it(in, fs::directory_options::skip_permission_denied, ec), end;
         !ec && it != end; it.increment(ec))
      take(*it);
  } else {
    for (fs::directory_iterator it(in, ec), end; !ec && it != end; it.increment(ec)) take(*it);
  }
}

// Unique stems in input order.
void name_items(std::vector<Item>& items) {
  std::set<std::string> used{"summary"};
  for (size_t k = 0; k < items.size(); ++k) items[k].index = k;
  for (Item& it : items) {
    std::string base = fs::path(it.input).stem().string();
    if (base.empty() || base == "." || base == "..") base = "input";
    std::string stem = base;
    for (int k = 2; used.count(stem); ++k) stem = base + "-" + std::to_string(k);
    used.insert(stem);
    it.stem = stem;
  }
}

}  // namespace

std::vector<Item> expand_inputs(const std::vector<std::string>& inputs, bool recursive,
                                std::vector<std::string>& ignored) {
  std::vector<Item> items;
  ignored.clear();
  for (const std::string& in : inputs) {
    std::error_code ec;
    const fs::file_status st = fs::status(in, ec);
    if (!ec && fs::is_directory(st)) {
      std::vector<std::string> files;
      list_folder(in, recursive, files, ignored, ec);
      if (ec) {
        Item bad;
        bad.input = in;
        bad.missing = in + ": cannot list the folder (" + ec.message() + ")";
        items.push_back(bad);
      }
      std::sort(files.begin(), files.end());
      for (auto& f : files) {
        Item it;
        it.input = f;
        items.push_back(it);
      }
    } else {
      Item it;
      it.input = in;
      if (ec || !fs::exists(st)) it.missing = in + ": no such file or folder";
      items.push_back(it);
    }
  }
  std::sort(ignored.begin(), ignored.end());
  name_items(items);
  return items;
}

std::vector<Item> select_shard(std::vector<Item> items, int shard, int shards) {
  if (shards <= 1) return items;
  std::vector<Item> mine;
  for (Item& it : items)
    if (it.index % static_cast<size_t>(shards) == static_cast<size_t>(shard - 1)) mine.push_back(std::move(it));
  return mine;
}

}  // namespace locus::runner
