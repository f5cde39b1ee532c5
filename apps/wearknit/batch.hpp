// wearknit batch: many plans from one manifest (docs/batch.md). The
// manifest, the rows' state under DIR/.batch/, and the summary; the verb
// (verb_batch.cpp) runs the rows locally or submits them to Slurm
// (batch_slurm.hpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace wearknit::cli {

// One row of the manifest: a plan into DIR/name.
struct BatchRow {
  int line = 0;  // of the manifest, for messages
  std::string name;
  std::string garment;  // as written, and resolved against the manifest's folder
  std::string wearer;
  std::filesystem::path garment_path;
  std::filesystem::path wearer_path;
  // Every other non-empty column: the plan option (`size_mm` -> --size-mm)
  // and its value, in the manifest's column order.
  std::vector<std::pair<std::string, std::string>> options;
};

struct Manifest {
  std::filesystem::path path;
  std::vector<BatchRow> rows;
};

// Reads a manifest: CSV (RFC 4180: commas, double-quoted fields with ""
// inside, CRLF or LF) with a header naming the columns `name`, `garment`,
// `wearer` and any option of `wearknit plan` (underscores for dashes).
// Returns the manifest, or nothing with the problems (MANIFEST:LINE: ...)
// in `problems`: a missing or unknown column, a row with too few or too many
// fields, a name that is empty, repeated or not a plain file name, an option
// the batch sets itself (output, threads, quiet, send).
std::optional<Manifest> read_manifest(const std::filesystem::path& path,
                                      std::vector<std::string>& problems);

// The plan's command line for a row (after `wearknit`), writing into
// dir/NAME with `threads` threads.
std::vector<std::string> plan_arguments(const BatchRow& row, const std::filesystem::path& dir,
                                        int threads);

// What decides a row's result: its options and the bytes of its garment and
// wearer. A row done with the same fingerprint is not run again. Nothing when
// an input cannot be read (the row then runs and fails with the plan's
// message).
std::optional<std::uint64_t> row_fingerprint(const BatchRow& row);

// A row's state, DIR/.batch/NAME.json: "running" from its start, then "ok"
// or "failed" with the plan's exit code and first error line.
struct RowState {
  std::string status;  // running, ok, failed
  std::uint64_t fingerprint = 0;
  int exit_code = -1;
  std::string error;
  double seconds = 0;
  std::string started;  // UTC, ISO 8601
};

std::filesystem::path batch_state_dir(const std::filesystem::path& dir);
std::optional<RowState> read_row_state(const std::filesystem::path& dir, const std::string& name);
// Written atomically; "" or the failure.
std::string write_row_state(const std::filesystem::path& dir, const std::string& name,
                            const RowState& state);

// Whether a row is done with these inputs: its state is ok with the same
// fingerprint (row_fingerprint of the row as it is now).
bool row_done(const std::filesystem::path& dir, const BatchRow& row,
              const std::optional<std::uint64_t>& fingerprint);

// Writes DIR/batch.json, DIR/batch.csv and DIR/index.html from the rows'
// states and their plan folders (plan.json, report.json). Returns "" or the
// failure. `ok_rows` receives how many rows are ok (done with the same
// inputs).
std::string write_batch_summary(const std::filesystem::path& dir, const Manifest& manifest,
                                std::size_t* ok_rows);

}  // namespace wearknit::cli
