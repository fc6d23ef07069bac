// The one progress bar of every long command (bench, trace, render, accuracy, csg, the report's
// stages), on stderr: label, bar, percent, elapsed time and an estimate of the rest.
//   On a terminal it is redrawn in place, within 79 columns, and cleared when done.
//   Otherwise (a log, CI) it prints one line per tenth of the run, and only once the run has taken
//   two seconds: short runs (the report's many small traces) leave no lines behind.
#pragma once

#include <chrono>
#include <iosfwd>
#include <string>

namespace rb::app {

// "45 s", "3 min 05 s", "1 h 02 min".
std::string format_duration(double seconds);

class ProgressBar {
 public:
  enum class Mode { automatic, terminal, lines, off };
  explicit ProgressBar(std::string label, Mode mode = Mode::automatic, std::ostream* out = nullptr);
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;
  // fraction in [0, 1]; `what`: the step under way (a benchmark's or a case's name).
  void update(double fraction, const std::string& what = "");
  // At `seconds` since the start: for tests, which cannot wait.
  void update_at(double fraction, const std::string& what, double seconds);
  void done();
  double seconds() const;

  // The terminal line: "LABEL [#####.....]  42 %  12 s, ~17 s left  WHAT", cut to `width`.
  static std::string line(const std::string& label, double fraction, double seconds, const std::string& what,
                          std::size_t width = 79);
  // The estimate of the rest: elapsed * (1 - f) / f; "" before 2 % or 1 s.
  static std::string remaining(double fraction, double seconds);

 private:
  std::string label_;
  Mode mode_;
  std::ostream* out_;
  int last_tenth_ = 0;
  bool drawn_ = false;
  std::chrono::steady_clock::time_point t0_ = std::chrono::steady_clock::now();
};

}  // namespace rb::app
