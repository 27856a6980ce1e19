// SPDX-License-Identifier: Apache-2.0
#include "guide/scan_feed.h"

#include <filesystem>
#include <utility>

#include "io/text/carmen_reader.h"
#include "recording/recording.h"
#include "recording/recording_streams.h"

namespace wallcal::guide {
namespace {

namespace fs = std::filesystem;

// The bytes that tell the containers apart (the longest magic: SQLite's 16).
constexpr uintmax_t kTellingBytes = 16;

// A CARMEN log read on from a byte, noting where each scan's line starts (for the next read).
class MarkedScans : public io::ScanSource {
 public:
  MarkedScans(const std::string& path, int64_t start_byte, int64_t first_line,
              std::vector<ScanMark>* marks)
      : reader_(path, start_byte, first_line), marks_(marks) {}
  bool Next(io::ScanRecord* scan) override {
    if (!reader_.Next(scan)) return false;
    marks_->push_back(ScanMark{scan->stamp_s, reader_.line_start_byte(), scan->line});
    return true;
  }
  bool NextStamp(double* stamp_s, int* line) override {
    if (!reader_.NextStamp(stamp_s, line)) return false;
    marks_->push_back(ScanMark{*stamp_s, reader_.line_start_byte(), *line});
    return true;
  }
  bool ParseCurrent(io::ScanRecord* scan) override { return reader_.ParseCurrent(scan); }
  const io::SkipCounts& skipped() const override { return reader_.skipped(); }
  int64_t scans_read() const override { return reader_.scans_read(); }
  const std::string& path() const override { return reader_.path(); }

 private:
  io::CarmenReader reader_;
  std::vector<ScanMark>* marks_;
};

// A CARMEN log, plain or gzip-compressed: read on from the text byte of the first scan not
// settled (a gzip log is inflated from its start up to there, not parsed).
class CarmenFeed : public ScanFeed {
 public:
  explicit CarmenFeed(std::string path) : path_(std::move(path)) {}
  FeedRead Update() override {
    FeedRead read;
    std::error_code error;
    read.log_bytes = static_cast<int64_t>(fs::file_size(path_, error));
    // A log only grows while it is written: a shorter one is a new log under the same name.
    read.restarted = !error && read.log_bytes < log_bytes_;
    if (!error) log_bytes_ = read.log_bytes;
    if (read.restarted) {
      resume_byte_ = 0;
      resume_line_ = 1;
    }
    read.from_byte = resume_byte_;
    return read;
  }
  std::unique_ptr<io::ScanSource> OpenAll() override {
    return std::make_unique<io::CarmenReader>(path_);
  }
  std::unique_ptr<io::ScanSource> OpenUnsettled(std::vector<ScanMark>* marks) override {
    marks->clear();
    return std::make_unique<MarkedScans>(path_, resume_byte_, resume_line_, marks);
  }
  void Settle(const std::vector<ScanMark>& marks, size_t settled) override {
    resume_byte_ = marks[settled].at;
    resume_line_ = marks[settled].line;
  }

 private:
  std::string path_;
  int64_t log_bytes_ = 0;    // the file's size at the last Update (compressed, for gzip)
  int64_t resume_byte_ = 0;  // of the log's text
  int64_t resume_line_ = 1;
};

// The kept scans of a recording, from the first not settled on, noting each one's place.
class KeptScans : public io::ScanSource {
 public:
  KeptScans(const std::vector<io::ScanRecord>* scans, std::string path,
            std::vector<ScanMark>* marks)
      : scans_(scans), path_(std::move(path)), marks_(marks) {}
  bool Next(io::ScanRecord* scan) override {
    if (next_ >= scans_->size()) return false;
    *scan = (*scans_)[next_];
    if (marks_ != nullptr) {
      marks_->push_back(ScanMark{scan->stamp_s, static_cast<int64_t>(next_), scan->line});
    }
    ++next_;
    return true;
  }
  const io::SkipCounts& skipped() const override { return skipped_; }
  int64_t scans_read() const override { return static_cast<int64_t>(next_); }
  const std::string& path() const override { return path_; }

 private:
  const std::vector<io::ScanRecord>* scans_;
  std::string path_;
  std::vector<ScanMark>* marks_;
  io::SkipCounts skipped_;
  size_t next_ = 0;
};

class RecordingFeed : public ScanFeed {
 public:
  RecordingFeed(const io::SessionSpec& session, const io::ScannerPreset* preset)
      : path_(session.scanner_log), tail_(session, preset) {}
  FeedRead Update() override {
    std::vector<io::ScanRecord> gained;
    const recording::TailRead read = tail_.ReadOn(&gained);
    if (read.restarted) unsettled_.clear();
    unsettled_.insert(unsettled_.end(), std::make_move_iterator(gained.begin()),
                      std::make_move_iterator(gained.end()));
    FeedRead feed;
    feed.restarted = read.restarted;
    feed.from_byte = static_cast<int64_t>(read.from_byte);
    feed.log_bytes = static_cast<int64_t>(read.file_bytes);
    return feed;
  }
  std::unique_ptr<io::ScanSource> OpenAll() override {
    // Nothing is settled before the first pass has given a start: the kept scans are all.
    return std::make_unique<KeptScans>(&unsettled_, path_, nullptr);
  }
  std::unique_ptr<io::ScanSource> OpenUnsettled(std::vector<ScanMark>* marks) override {
    marks->clear();
    return std::make_unique<KeptScans>(&unsettled_, path_, marks);
  }
  void Settle(const std::vector<ScanMark>& marks, size_t settled) override {
    unsettled_.erase(unsettled_.begin(), unsettled_.begin() + marks[settled].at);
  }

 private:
  std::string path_;
  recording::ScanTail tail_;
  std::vector<io::ScanRecord> unsettled_;
};

}  // namespace

std::unique_ptr<ScanFeed> ScanFeed::For(const io::SessionSpec& session,
                                        const io::ScannerPreset* preset) {
  const std::string& log = session.scanner_log;
  std::error_code error;
  if (fs::is_directory(log, error)) {
    if (!recording::IsRecording(log)) {
      // `ros2 bag record` makes the folder, then its first storage file.
      throw io::InputError(io::Where(log, 0,
                                     "a folder without a storage file yet; expected a rosbag2 "
                                     "folder (metadata.yaml, .db3 or .mcap files)"));
    }
  } else if (fs::file_size(log, error) < kTellingBytes && !error) {
    throw io::InputError(io::Where(log, 0,
                                   "too short yet to tell a text log from a recording; expected "
                                   "at least " + std::to_string(kTellingBytes) + " bytes"));
  }
  if (recording::ScanTail::Supports(log)) return std::make_unique<RecordingFeed>(session, preset);
  return std::make_unique<CarmenFeed>(log);
}

}  // namespace wallcal::guide
