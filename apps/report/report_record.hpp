// What a report measured, kept beside it (OUT/measured.json) so that `raybench report --from OUT`
// writes the document again without measuring: a section asks for each measurement by a name; while
// measuring, the record runs it and keeps its JSON under that name; while replaying, it returns the
// kept JSON. Every figure a section prints comes out of such a measurement, so a replayed section
// writes the page a measured one would have written from the same figures.
#pragma once

#include <nlohmann/json.hpp>

#include <functional>
#include <stdexcept>
#include <string>

namespace rb::app {

class Record {
 public:
  // A record that measures (a new report).
  Record() = default;
  // A record that replays what a report kept in `file`. Throws std::runtime_error naming the file
  // when it is not one, is of another format, or its digest does not match its measurements.
  static Record replaying(const std::string& file);

  bool replay() const { return replay_; }
  // The measurement `name`: measured now (and kept), or the kept one. Replaying a name the file does
  // not hold throws std::runtime_error naming the file and the measurement (a report of another
  // version, or of other options).
  nlohmann::json take(const std::string& name, const std::function<nlohmann::json()>& measure);
  // Everything measured so far, as OUT/measured.json holds it: the measurements with the record's
  // format and a digest of them (a record edited or damaged since is refused, not half read).
  nlohmann::json document() const;
  const std::string& file() const { return file_; }

 private:
  nlohmann::json kept_ = nlohmann::json::object();
  bool replay_ = false;
  std::string file_;
};

}  // namespace rb::app
