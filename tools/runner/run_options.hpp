// The command line of `locus run` (README "locus run"): the runner's own
// options, and everything else passed through to the pipeline unchanged.
#pragma once
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace locus::runner {

// JSON objects keep their keys in insertion order, as in the CLI's outputs.
using Json = nlohmann::ordered_json;

struct RunOptions {
  std::string pipeline;
  std::vector<std::string> inputs;
  std::vector<std::string> pipeline_args;
  std::string out;
  int jobs = 1;
  int threads = 0;
  std::string ext;  // after parsing: the -o extension, "" = the runner passes no -o
  bool json = false;
  bool recursive = false;  // --recursive: folders include their subfolders
  bool resume = false;     // --resume: skip items whose report says ok for the same command line
  int shard = 1, shards = 1;  // --shard K/N: every N-th input of the sorted list, from the K-th
  std::vector<std::string> merge;  // --merge DIR...: combine shard summaries, run nothing
  bool preview = false;  // --preview: every item writes DIR/STEM.png (hks with several t: DIR/STEM-tK.png)
};

// Parses argv (argv[1] == "run"). Prints the usage and exits 0 for -h/--help;
// throws Error(BadUsage) naming the offending argument.
RunOptions parse_run_args(int argc, char** argv, const std::vector<std::string>& commands);

// Error(BadUsage) with the message prefixed by "run: ".
[[noreturn]] void usage_error(const std::string& msg);

}  // namespace locus::runner
