#include "devices/device_engine.hpp"

#include <fcntl.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "devices/debug.hpp"
#include "devices/file_view.hpp"
#include "knitout/output_file.hpp"

namespace devices {
namespace {

// Writes `text` to `path` via a temporary name and a rename, so a reader (or
// a restarted device) sees the old or the new file, never half of one. With
// `sync` the data is fsync'ed first (knitout::write_file_atomically does the
// same); without, only the rename's atomicity remains, which is what a
// simulated power cycle inside one process can observe.
void write_atomically(const std::filesystem::path& path, const std::string& text, bool sync) {
  if (sync) {
    const std::string failure =
        knitout::write_file_atomically(path.string(), [&](std::ostream& out) { out << text; });
    if (!failure.empty()) throw std::runtime_error("mock device: " + failure);
    return;
  }
  const std::filesystem::path tmp = path.string() + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << text;
    if (!out) throw std::runtime_error("mock device: cannot write " + tmp.string());
  }
  std::filesystem::rename(tmp, path);
}

void append_and_sync(const std::filesystem::path& path, std::span<const std::uint8_t> bytes,
                     bool sync) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (fd < 0) throw std::runtime_error("mock device: cannot open " + path.string());
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0) {
      ::close(fd);
      throw std::runtime_error("mock device: cannot write " + path.string());
    }
    done += static_cast<std::size_t>(n);
  }
  if (sync && ::fdatasync(fd) != 0) {
    ::close(fd);
    throw std::runtime_error("mock device: cannot sync " + path.string());
  }
  ::close(fd);
}

Bytes read_all(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return Bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// JSON text of `j`; bytes that are not UTF-8 (a refusal reason may quote
// them from a job) are written as U+FFFD rather than stopping the device.
std::string json_text(const nlohmann::json& j) {
  return j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

// The check of a complete job (docs/protocol.md §4): size, SHA-256, row
// count and the format's checker. Returns the reason to refuse it, or an
// empty string. Runs on a worker thread for large jobs: it reads the file
// through a memory map and touches nothing else.
std::string check_job(const std::filesystem::path& file, const ManifestMessage& manifest,
                      const JobCheckers& checkers) {
  try {
    auto mapped = MappedFile::open(file);
    if (!mapped) return "[J007] the device cannot read its copy: " + mapped.error().text();
    const std::span<const std::uint8_t> bytes = mapped.value().bytes();
    if (bytes.size() != manifest.size) {
      return "[J004] received " + std::to_string(bytes.size()) + " bytes, the manifest says " +
             std::to_string(manifest.size);
    }
    const Sha256 digest = sha256(bytes);
    if (digest != manifest.sha256) {
      return "[J005] SHA-256 of the received bytes " + to_hex(digest) +
             " differs from the manifest's " + to_hex(manifest.sha256);
    }
    auto rows = split_rows(manifest.format, bytes);
    if (!rows) return "[J006] " + rows.error().message;
    if (rows.value().size() - 1 != manifest.rows) {
      return "[J006] the job has " + std::to_string(rows.value().size() - 1) +
             " rows, the manifest says " + std::to_string(manifest.rows);
    }
    const auto& check = manifest.format == JobFormat::Dat ? checkers.dat : checkers.knitout;
    return check ? check(manifest.name, bytes) : std::string();
  } catch (const std::bad_alloc&) {
    return "[J007] the device ran out of memory checking the job";
  } catch (const std::exception& e) {
    // A checker that fails in itself refuses the job; it never takes the
    // device down.
    return std::string("[J007] the device could not check the job: ") + e.what();
  }
}

JobState state_from_string(const std::string& s) {
  for (int i = 0; i <= 7; ++i) {
    if (to_string(static_cast<JobState>(i)) == s) return static_cast<JobState>(i);
  }
  throw std::runtime_error("mock device: unknown state '" + s + "' in state.json");
}

}  // namespace

Result<std::unique_ptr<DeviceEngine>> DeviceEngine::open(DeviceConfig config) {
  std::unique_ptr<DeviceEngine> engine(new DeviceEngine(std::move(config)));
  std::error_code ec;
  std::filesystem::create_directories(engine->state_dir(), ec);
  if (ec) {
    return Error{ErrorClass::OsFailure, "cannot create " + engine->state_dir().string(),
                 ec.value()};
  }
  Outcome loaded = engine->load();
  if (!loaded) return loaded.error();
  return engine;
}

DeviceEngine::~DeviceEngine() {
  if (check_.valid()) check_.wait();
}

std::filesystem::path DeviceEngine::part_path() const {
  return state_dir() / ("job-" + std::to_string(job_id_) + ".part");
}

std::filesystem::path DeviceEngine::knit_log_path(std::uint32_t job_id) const {
  return state_dir() / ("job-" + std::to_string(job_id) + ".knitlog");
}

void DeviceEngine::event(const std::string& text) const {
  debug_line("device: " + text);
  if (config_.on_event) config_.on_event(text);
}

void DeviceEngine::reset_state() {
  job_id_ = 0;
  state_ = JobState::Idle;
  paused_ = false;
  alarm_ = Alarm::None;
  yarn_break_fired_ = false;
  stop_fired_ = false;
  manifest_ = ManifestMessage{};
  received_ = 0;
  bytes_received_ = 0;
  knitted_ = 0;
  reason_.clear();
  write_through_ = false;
}

void DeviceEngine::remove_stale_temporaries() {
  // A power cut between creating a temporary file and renaming it leaves
  // the temporary behind; no job may be named like one (job_name_problem).
  std::error_code ec;
  for (const auto& folder : {config_.store, state_dir()}) {
    for (auto it = std::filesystem::directory_iterator(folder, ec);
         !ec && it != std::filesystem::directory_iterator(); it.increment(ec)) {
      const std::string name = it->path().filename().string();
      const bool temporary =
          name.find(".tmp-") != std::string::npos || (name.size() > 4 && name.ends_with(".tmp"));
      if (!temporary || !it->is_regular_file()) continue;
      std::error_code removed;
      std::filesystem::remove(it->path(), removed);
      if (!removed) event("removed the temporary file " + it->path().string() + " of a power cut");
    }
  }
}

void DeviceEngine::quarantine_job(const std::string& why) {
  const std::filesystem::path folder =
      state_dir() / "quarantine" / ("job-" + std::to_string(job_id_));
  std::error_code ec;
  std::filesystem::create_directories(folder, ec);
  for (const auto& file : {part_path(), knit_log_path(job_id_)}) {
    if (std::filesystem::exists(file, ec))
      std::filesystem::rename(file, folder / file.filename(), ec);
  }
  reason_ = why + "; its files are in " + folder.string();
  state_ = JobState::Refused;
  paused_ = false;
  save();
  event("job " + printable_name(manifest_.name) + ": quarantined: " + reason_);
}

Outcome DeviceEngine::load() {
  if (check_.valid()) check_.wait();  // a power cut ends the check; its answer is lost
  check_ = {};
  const auto path = state_dir() / "state.json";
  clear_buffers();
  reset_state();
  knit_origin_s_ = -1;
  remove_stale_temporaries();
  if (!std::filesystem::exists(path)) return Ok{};
  nlohmann::json j;
  try {
    std::ifstream in(path);
    j = nlohmann::json::parse(in);
    job_id_ = j.at("job_id").get<std::uint32_t>();
    state_ = state_from_string(j.at("state").get<std::string>());
    paused_ = j.at("paused").get<bool>();
    alarm_ = static_cast<Alarm>(j.at("alarm").get<int>());
    yarn_break_fired_ = j.at("yarn_break_fired").get<bool>();
    stop_fired_ = j.at("stop_fired").get<bool>();
    manifest_.name = j.at("name").get<std::string>();
    manifest_.format = static_cast<JobFormat>(j.at("format").get<int>());
    manifest_.size = j.at("size").get<std::uint64_t>();
    manifest_.rows = j.at("rows_total").get<std::uint32_t>();
    const std::string hex = j.at("sha256").get<std::string>();
    for (std::size_t i = 0; i < 32 && 2 * i + 1 < hex.size(); ++i) {
      manifest_.sha256[i] = static_cast<std::uint8_t>(std::stoi(hex.substr(2 * i, 2), nullptr, 16));
    }
    received_ = j.at("rows_received").get<std::uint32_t>();
    bytes_received_ = j.at("bytes_received").get<std::uint64_t>();
    reason_ = j.at("reason").get<std::string>();
    jobs_done_ = j.at("jobs_done").get<std::uint64_t>();
    rows_knitted_total_ = j.at("rows_knitted_total").get<std::uint64_t>();
  } catch (const std::exception& e) {
    // A state the device cannot read (a damaged disk, a file from another
    // program) is set aside, never a reason to stay down: the device comes
    // up idle, and a host that resumes learns the job is gone.
    const std::filesystem::path kept =
        state_dir() / "quarantine" /
        ("state-" +
         std::to_string(std::chrono::duration_cast<std::chrono::seconds>(
                            std::chrono::system_clock::now().time_since_epoch())
                            .count()) +
         ".json");
    std::error_code ec;
    std::filesystem::create_directories(kept.parent_path(), ec);
    std::filesystem::rename(path, kept, ec);
    if (ec) {
      return make_error(ErrorClass::OsFailure, path.string() + ": unreadable device state (" +
                                                   e.what() +
                                                   ") that cannot be moved aside: " + ec.message());
    }
    reset_state();  // the fields read before the failure
    event("unreadable device state " + path.string() + " (" + e.what() + "): kept as " +
          kept.string() + "; the device starts idle");
    return Ok{};
  }
  if (job_unfinished(state_)) {
    if (std::string problem = job_name_problem(manifest_.name); !problem.empty()) {
      // Stored by an earlier version that took such names: it cannot be
      // stored under its name, so it is refused and its files set aside.
      manifest_.name = printable_name(manifest_.name);
      quarantine_job("[J009] refused on start: " + problem);
      return Ok{};
    }
  }
  write_through_ = state_ == JobState::Receiving;
  // Rows past the durable counter may have reached the spool before a power
  // cut; they were never acknowledged as durable, so drop them.
  if (state_ == JobState::Receiving && std::filesystem::exists(part_path())) {
    std::filesystem::resize_file(part_path(), bytes_received_);
  }
  knitted_ = 0;
  if (job_id_ != 0 && std::filesystem::exists(knit_log_path(job_id_))) {
    // A log that is not 0..k-1 in order means the device knitted a row twice
    // or skipped one: a broken invariant, not bad input.
    const Bytes log = read_all(knit_log_path(job_id_));
    std::uint32_t lines = 0;
    std::size_t at = 0;
    while (at < log.size()) {
      const auto nl = std::find(log.begin() + static_cast<std::ptrdiff_t>(at), log.end(), '\n');
      if (nl == log.end()) break;  // a torn last line: not knitted
      const std::string line(log.begin() + static_cast<std::ptrdiff_t>(at), nl);
      if (line != std::to_string(lines)) {
        throw std::logic_error("mock device: knit log " + knit_log_path(job_id_).string() +
                               " line " + std::to_string(lines + 1) + " is '" + line +
                               "', expected row " + std::to_string(lines));
      }
      ++lines;
      at = static_cast<std::size_t>(nl - log.begin()) + 1;
    }
    knitted_ = lines;
  }
  return Ok{};
}

void DeviceEngine::save() {
  nlohmann::json j;
  j["job_id"] = job_id_;
  j["state"] = std::string(to_string(state_));
  j["paused"] = paused_;
  j["alarm"] = static_cast<int>(alarm_);
  j["yarn_break_fired"] = yarn_break_fired_;
  j["stop_fired"] = stop_fired_;
  j["name"] = manifest_.name;
  j["format"] = static_cast<int>(manifest_.format);
  j["size"] = manifest_.size;
  j["rows_total"] = manifest_.rows;
  j["sha256"] = to_hex(manifest_.sha256);
  j["rows_received"] = received_;
  j["bytes_received"] = bytes_received_;
  j["rows_knitted"] = knitted_;  // informative; the knit log is the counter
  j["reason"] = reason_;
  j["jobs_done"] = jobs_done_;
  j["rows_knitted_total"] = rows_knitted_total_;
  write_atomically(state_dir() / "state.json", json_text(j), config_.sync);
}

JobState DeviceEngine::state() const {
  if (paused_ && state_ == JobState::Knitting) return JobState::Paused;
  return state_;
}

StatusMessage DeviceEngine::status() const {
  StatusMessage s;
  s.capabilities = kCapPause | kCapCancel | kCapAlarms | kCapResume;
  s.buffer_capacity = config_.buffer_rows;
  s.buffer_free = free_rows();
  s.max_row_bytes = static_cast<std::uint32_t>(kMaxPayload);
  s.state = state();
  s.alarm = alarm_;
  s.format = manifest_.format;
  s.rows_total = manifest_.rows;
  s.rows_received = accepted();
  s.rows_knitted = knitted_;
  s.sha256 = manifest_.sha256;
  s.name = manifest_.name;
  s.reason = reason_;
  s.rows_durable = received_;
  return s;
}

void DeviceEngine::refuse(std::string reason) {
  reason_ = std::move(reason);
  state_ = JobState::Refused;
  clear_buffers();
  std::error_code ec;
  std::filesystem::remove(part_path(), ec);
  save();
  event("job " + manifest_.name + ": refused: " + reason_);
}

void DeviceEngine::refuse_for_store_failure(const std::exception& failure) {
  // The store could not take a row or a file (a full or failing disk): the
  // job is refused with the reason, and the device keeps serving. When even
  // the refusal cannot be written, the failure stops the device.
  refuse(std::string("[J007] the device's store cannot take the job: ") + failure.what());
}

void DeviceEngine::handle(const Frame& frame, double now_s, std::vector<Frame>& replies) {
  try {
    handle_frame(frame, now_s, replies);
  } catch (const std::runtime_error& failure) {
    if (state_ != JobState::Receiving) throw;
    refuse_for_store_failure(failure);
    replies.push_back(Frame{FrameType::Status, 0, job_id_, frame.seq, encode(status())});
  }
}

void DeviceEngine::tick(double now_s) {
  try {
    advance(now_s);
  } catch (const std::runtime_error& failure) {
    if (state_ != JobState::Receiving) throw;
    refuse_for_store_failure(failure);
  }
}

void DeviceEngine::handle_frame(const Frame& frame, double now_s, std::vector<Frame>& replies) {
  const auto reply_status = [&] {
    replies.push_back(Frame{FrameType::Status, 0, job_id_, frame.seq, encode(status())});
  };
  switch (frame.type) {
    case FrameType::Hello:
    case FrameType::StatusRequest:
      tick(now_s);  // answer with the counters as of now
      reply_status();
      return;
    case FrameType::Manifest: {
      ManifestMessage m;
      if (!decode(frame.payload, m) || frame.job_id == 0) return;  // malformed: ignore
      if (frame.job_id == job_id_ || job_unfinished(state_)) {
        reply_status();  // idempotent, or busy with another job: the host decides
        return;
      }
      if (check_.valid()) check_.wait();  // the check of a cancelled job
      check_ = {};
      job_id_ = frame.job_id;
      manifest_ = m;
      received_ = 0;
      bytes_received_ = 0;
      knitted_ = 0;
      paused_ = false;
      alarm_ = Alarm::None;
      yarn_break_fired_ = false;
      stop_fired_ = false;
      reason_.clear();
      write_through_ = false;
      clear_buffers();
      std::error_code ec;
      std::filesystem::remove(part_path(), ec);
      std::filesystem::remove(knit_log_path(job_id_), ec);
      // The name is checked before anything derived from it touches the
      // disk; a refused one is kept in printable form (docs/protocol.md §7).
      const std::string name_problem = job_name_problem(m.name);
      if (!name_problem.empty()) manifest_.name = printable_name(m.name);
      struct statvfs disk {};
      const std::uint64_t free_bytes =
          ::statvfs(config_.store.c_str(), &disk) == 0
              ? static_cast<std::uint64_t>(disk.f_bavail) * disk.f_frsize
              : std::numeric_limits<std::uint64_t>::max();
      if (!name_problem.empty()) {
        refuse(name_problem);
      } else if (m.format != JobFormat::Dat && m.format != JobFormat::Knitout) {
        refuse("[J002] unknown job format " + std::to_string(static_cast<int>(m.format)));
      } else if (m.rows == 0 || m.size == 0) {
        refuse("[J003] the manifest announces an empty job");
      } else if (m.size > config_.max_job_bytes || m.size > free_bytes) {
        refuse("[J008] the job is " + std::to_string(m.size) + " bytes; the device takes " +
               std::to_string(std::min(config_.max_job_bytes, free_bytes)) +
               " (its limit, or its store's free space)");
      } else {
        state_ = JobState::Receiving;
        append_and_sync(part_path(), {}, config_.sync);
        save();
        event("job " + m.name + ": manifest accepted (" + std::string(to_string(m.format)) + ", " +
              std::to_string(m.size) + " bytes, " + std::to_string(m.rows) + " rows, sha256 " +
              to_hex(m.sha256) + ")");
      }
      reply_status();
      return;
    }
    case FrameType::Row: {
      if (frame.job_id == job_id_ && state_ == JobState::Receiving && !check_.valid() &&
          frame.seq < manifest_.rows && frame.payload.size() <= manifest_.size) {
        take_row(frame.seq, frame.payload);
      }
      // Cumulative: duplicates are answered, never applied; a row past a
      // gap waits in the buffer until the gap is filled.
      AckMessage ack{state(), accepted(), knitted_, free_rows()};
      replies.push_back(Frame{FrameType::Ack, 0, job_id_, frame.seq, encode(ack)});
      return;
    }
    case FrameType::Command: {
      CommandMessage c;
      if (!decode(frame.payload, c)) return;
      if (frame.job_id == job_id_ && job_unfinished(state_)) {
        switch (c.command) {
          case Command::Pause:
            if (!paused_) {
              paused_ = true;
              save();
              event("job " + manifest_.name + ": paused at row " + std::to_string(knitted_));
            }
            break;
          case Command::Resume:
            if (paused_ || state_ == JobState::Alarm) {
              paused_ = false;
              if (state_ == JobState::Alarm) {
                state_ = JobState::Knitting;
                alarm_ = Alarm::None;
              }
              knit_origin_s_ = -1;
              save();
              event("job " + manifest_.name + ": resumed at row " + std::to_string(knitted_));
            }
            break;
          case Command::Cancel:
            state_ = JobState::Cancelled;
            clear_buffers();
            {
              std::error_code ec;
              std::filesystem::remove(part_path(), ec);
            }
            save();
            event("job " + manifest_.name + ": cancelled after " + std::to_string(knitted_) +
                  " of " + std::to_string(manifest_.rows) + " rows");
            break;
        }
      }
      tick(now_s);
      reply_status();
      return;
    }
    case FrameType::Status:
    case FrameType::Ack:
      return;  // a device does not take device messages
  }
}

void DeviceEngine::clear_buffers() {
  buffer_.clear();
  buffered_bytes_ = 0;
  ahead_.clear();
  ahead_bytes_ = 0;
}

std::uint32_t DeviceEngine::free_rows() const {
  const std::size_t held = buffer_.size() + ahead_.size();
  return held >= config_.buffer_rows ? 0 : config_.buffer_rows - static_cast<std::uint32_t>(held);
}

void DeviceEngine::take_row(std::uint32_t row, const Bytes& payload) {
  const std::uint32_t next = accepted();
  if (row < next || ahead_.count(row) != 0) return;  // a duplicate
  const std::uint64_t held = bytes_received_ + buffered_bytes_ + ahead_bytes_;
  if (held + payload.size() > manifest_.size) return;  // cannot be part of this job
  if (row == next) {
    // The row everything waits for is taken even into a full buffer (the
    // rows held ahead of it then move on), so the buffer cannot jam.
    if (free_rows() == 0 && ahead_.empty()) return;
    buffered_bytes_ += payload.size();
    buffer_.push_back(payload);
    // Rows that arrived ahead of it now follow in order.
    for (auto it = ahead_.find(accepted()); it != ahead_.end(); it = ahead_.find(accepted())) {
      ahead_bytes_ -= it->second.size();
      buffered_bytes_ += it->second.size();
      buffer_.push_back(std::move(it->second));
      ahead_.erase(it);
    }
  } else {
    // Past a gap: held (selective repeat) while there is room, so one lost
    // row costs one resend, not the whole window.
    if (free_rows() == 0 || row >= next + config_.buffer_rows) return;
    ahead_bytes_ += payload.size();
    ahead_.emplace(row, payload);
  }
  // A full buffer goes to the store at once, so the acknowledgement can
  // open the window again without the host having to ask. After a power
  // cut lost the buffer, every row goes to the store before its
  // acknowledgement.
  if (write_through_ || buffer_.size() + ahead_.size() >= config_.buffer_rows) flush_buffer();
}

void DeviceEngine::flush_buffer() {
  if (buffer_.empty()) return;
  Bytes joined;
  joined.reserve(buffered_bytes_);
  for (const Bytes& row : buffer_) joined.insert(joined.end(), row.begin(), row.end());
  append_and_sync(part_path(), joined, config_.sync);
  received_ += static_cast<std::uint32_t>(buffer_.size());
  bytes_received_ += joined.size();
  buffer_.clear();
  buffered_bytes_ = 0;
  save();
}

void DeviceEngine::start_check() {
  const std::filesystem::path target = config_.store / manifest_.name;
  const std::filesystem::path file = std::filesystem::exists(part_path()) ? part_path() : target;
  if (manifest_.size <= config_.background_check_bytes) {
    std::promise<std::string> done;
    done.set_value(check_job(file, manifest_, config_.checkers));
    check_ = done.get_future();
    return;
  }
  event("job " + manifest_.name + ": all " + std::to_string(manifest_.rows) +
        " rows arrived; checking it");
  check_ =
      std::async(std::launch::async, [file, manifest = manifest_, checkers = config_.checkers] {
        return check_job(file, manifest, checkers);
      });
}

void DeviceEngine::finish_check() {
  if (!check_.valid() || check_.wait_for(std::chrono::seconds(0)) != std::future_status::ready) {
    return;
  }
  std::string reason = check_.get();
  if (!reason.empty()) {
    refuse(std::move(reason));
    return;
  }
  store_job();
}

void DeviceEngine::store_job() {
  const std::filesystem::path target = config_.store / manifest_.name;
  if (std::filesystem::exists(part_path())) {
    std::error_code ec;
    std::filesystem::rename(part_path(), target, ec);
    if (ec) throw std::runtime_error("cannot store " + target.string() + ": " + ec.message());
    if (config_.sync) {
      const int dir = ::open(config_.store.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
      if (dir >= 0) {
        ::fsync(dir);
        ::close(dir);
      }
    }
  }
  nlohmann::json m;
  m["name"] = manifest_.name;
  m["format"] = std::string(to_string(manifest_.format));
  m["size"] = manifest_.size;
  m["rows"] = manifest_.rows;
  m["sha256"] = to_hex(manifest_.sha256);
  m["job_id"] = job_id_;
  write_atomically(config_.store / (manifest_.name + ".manifest.json"), json_text(m), config_.sync);
  state_ = JobState::Knitting;
  knit_origin_s_ = -1;
  save();
  event("job " + manifest_.name + ": stored " + target.string() + " (" +
        std::to_string(manifest_.size) + " bytes, sha256 verified, check passed)");
}

void DeviceEngine::knit(double now_s) {
  if (state_ != JobState::Knitting || paused_) return;
  if (knit_origin_s_ < 0) {
    knit_origin_s_ = now_s;
    knit_origin_rows_ = knitted_;
  }
  std::uint64_t target = manifest_.rows;
  if (config_.rows_per_s > 0) {
    // A clock that steps back knits nothing rather than a huge number of rows.
    const double elapsed = std::max(0.0, now_s - knit_origin_s_);
    target =
        knit_origin_rows_ + static_cast<std::uint64_t>(std::floor(elapsed * config_.rows_per_s));
  }
  target = std::min<std::uint64_t>(target, manifest_.rows);
  Alarm raise = Alarm::None;
  const auto limit = [&](std::uint32_t row, bool fired, Alarm kind) {
    if (row != 0 && !fired && row <= target && row > knitted_ && row <= manifest_.rows) {
      target = row;
      raise = kind;
    }
  };
  limit(config_.yarn_break_at_row, yarn_break_fired_, Alarm::YarnBreak);
  limit(config_.stop_at_row, stop_fired_, Alarm::Stop);
  if (target > knitted_) {
    std::string lines;
    for (std::uint64_t row = knitted_; row < target; ++row) lines += std::to_string(row) + "\n";
    append_and_sync(knit_log_path(job_id_),
                    std::span(reinterpret_cast<const std::uint8_t*>(lines.data()), lines.size()),
                    config_.sync);
    knitted_ = static_cast<std::uint32_t>(target);
  }
  if (raise != Alarm::None) {
    alarm_ = raise;
    (raise == Alarm::YarnBreak ? yarn_break_fired_ : stop_fired_) = true;
    state_ = JobState::Alarm;
    save();
    event("job " + manifest_.name + ": alarm: " + std::string(to_string(raise)) + " after row " +
          std::to_string(knitted_));
    return;
  }
  if (knitted_ == manifest_.rows) {
    auto log = verify_knit_log(job_id_, manifest_.rows);
    if (!log || log.value() != manifest_.rows) {
      throw std::logic_error(
          "mock device: knit log of job " + std::to_string(job_id_) + ": " +
          (log ? "holds " + std::to_string(log.value()) + " rows" : log.error().message));
    }
    state_ = JobState::Done;
    ++jobs_done_;
    rows_knitted_total_ += manifest_.rows;
    save();
    event("job " + manifest_.name + ": done: knitted " + std::to_string(knitted_) + "/" +
          std::to_string(manifest_.rows) + " rows, each exactly once");
  }
}

void DeviceEngine::advance(double now_s) {
  if (state_ != JobState::Receiving && state_ != JobState::Knitting) return;
  if (state_ == JobState::Receiving) {
    flush_buffer();
    if (received_ == manifest_.rows && !check_.valid()) start_check();
    finish_check();
  }
  knit(now_s);
}

void DeviceEngine::reboot(double now_s) {
  event("power cycle: the row buffer is lost, counters are read back");
  Outcome loaded = load();
  if (!loaded) throw std::runtime_error("mock device: " + loaded.error().message);
  (void)now_s;
}

Result<std::uint32_t> DeviceEngine::verify_knit_log(std::uint32_t job_id,
                                                    std::uint32_t rows) const {
  const Bytes log = read_all(knit_log_path(job_id));
  std::istringstream in(std::string(log.begin(), log.end()));
  std::vector<int> seen(rows, 0);
  std::string line;
  std::uint32_t count = 0;
  while (std::getline(in, line)) {
    const long row = std::strtol(line.c_str(), nullptr, 10);
    if (row < 0 || row >= static_cast<long>(rows) || std::to_string(row) != line) {
      return make_error(ErrorClass::Protocol, "knit log line " + std::to_string(count + 1) +
                                                  " holds '" + line + "', not a row of the job");
    }
    if (++seen[static_cast<std::size_t>(row)] > 1) {
      return make_error(ErrorClass::Protocol, "row " + line + " was knitted twice");
    }
    ++count;
  }
  for (std::uint32_t row = 0; row < count; ++row) {
    if (seen[row] != 1) {
      return make_error(ErrorClass::Protocol,
                        "row " + std::to_string(row) + " is missing from the knit log");
    }
  }
  return count;
}

}  // namespace devices
