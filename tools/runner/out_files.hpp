// The files of `locus run` in its --out folder, per input STEM: STEM.EXT (the
// pipeline's -o output), STEM.png (--preview), STEM.json (the item report);
// summary.json or summary-K-of-N.json; the hidden capture files of running
// children (.STEM.stdout.XXXXXX, .STEM.stderr.XXXXXX).
#pragma once
#include <filesystem>
#include <string>

namespace locus::runner {

std::filesystem::path report_path(const std::filesystem::path& out_dir, const std::string& stem);
std::filesystem::path output_path(const std::filesystem::path& out_dir, const std::string& stem, const std::string& ext);
std::filesystem::path preview_path(const std::filesystem::path& out_dir, const std::string& stem);
// summary.json, or summary-K-of-N.json for shard K of N > 1.
std::filesystem::path summary_path(const std::filesystem::path& out_dir, int shard, int shards);

// A unique, empty capture file in DIR (".STEM.KIND.XXXXXX"): two runs over one
// folder never share one. Error(BadInput) when it cannot be created.
std::string make_capture(const std::filesystem::path& out_dir, const std::string& stem, const char* kind);

// The whole file, or "" when it cannot be read.
std::string slurp(const std::filesystem::path& p);

}  // namespace locus::runner
