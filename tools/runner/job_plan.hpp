// The items of a `locus run`: the inputs expanded (a folder stands for the
// mesh files inside it, sorted by name), each with a unique stem that names
// its files in the --out folder, and the deterministic --shard split.
#pragma once
#include <sys/types.h>

#include <chrono>
#include <cstddef>
#include <string>
#include <vector>

namespace locus::runner {

struct Item {
  size_t index = 0;  // position in the sorted list of every input (before --shard)
  std::string input;
  std::string stem;     // unique within DIR
  std::string missing;  // non-empty: the input could not be listed (reported as failed, not run)
  // Result.
  std::string status = "not_run";
  int exit_status = -1, signal = 0;
  double seconds = 0;
  pid_t pid = -1;
  std::chrono::steady_clock::time_point start;
  std::string out_capture, err_capture;  // the child's stdout / stderr, unique temporary files in DIR
  bool resumed = false;                  // --resume found an ok report for this item
};

// Every input in order (folders expanded: the .off/.obj/.ply files directly
// inside, or at any depth when `recursive`, sorted by path), each with its
// index and a stem unique among all of them ("-2", "-3" appended when two
// inputs share one; "summary" is taken). Other files found in the folders go
// to `ignored`, sorted; a missing input or an unlistable folder becomes an
// item with `missing` set.
std::vector<Item> expand_inputs(const std::vector<std::string>& inputs, bool recursive,
                                std::vector<std::string>& ignored);

// The K-th of N parts (1-based): every N-th item of the full list, from the K-th.
std::vector<Item> select_shard(std::vector<Item> items, int shard, int shards);

}  // namespace locus::runner
