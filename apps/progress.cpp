#include "apps/progress.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <unistd.h>

namespace rb::app {

std::string format_duration(double s) {
  if (!(s >= 0)) s = 0;
  const long t = std::lround(s);
  if (t < 60) return fmt::format("{} s", t);
  if (t < 3600) return fmt::format("{} min {:02d} s", t / 60, t % 60);
  return fmt::format("{} h {:02d} min", t / 3600, (t % 3600) / 60);
}

ProgressBar::ProgressBar(std::string label, Mode mode, std::ostream* out) : label_(std::move(label)), mode_(mode), out_(out ? out : &std::cerr) {
  if (mode_ == Mode::automatic) mode_ = isatty(2) ? Mode::terminal : Mode::lines;
}

double ProgressBar::seconds() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count(); }

std::string ProgressBar::remaining(double f, double s) {
  if (f < 0.02 || s < 1 || f >= 1) return "";
  return "~" + format_duration(s * (1 - f) / f) + " left";
}

std::string ProgressBar::line(const std::string& label, double f, double s, const std::string& what, std::size_t width) {
  f = std::clamp(f, 0.0, 1.0);
  constexpr int kBar = 20;
  const int k = int(f * kBar + 0.5);
  std::string t = fmt::format("{} [{}{}] {:3.0f} % {}", label, std::string(std::size_t(k), '#'), std::string(std::size_t(kBar - k), '.'),
                              100 * f, format_duration(s));
  const std::string rest = remaining(f, s);
  if (!rest.empty()) t += ", " + rest;
  if (!what.empty()) t += "  " + what;
  if (t.size() > width) t = t.substr(0, width);
  return t;
}

void ProgressBar::update(double fraction, const std::string& what) { update_at(fraction, what, seconds()); }

void ProgressBar::update_at(double f, const std::string& what, double s) {
  f = std::clamp(f, 0.0, 1.0);
  if (mode_ == Mode::terminal) {
    *out_ << "\r\x1b[K" << line(label_, f, s, what) << std::flush;
    drawn_ = true;
  } else if (mode_ == Mode::lines) {
    const int tenth = int(f * 10 + 1e-9);
    if (tenth > last_tenth_ && s >= 2.0) {
      last_tenth_ = tenth;
      std::string t = fmt::format("{}: {:3d} % after {}", label_, tenth * 10, format_duration(s));
      const std::string rest = remaining(f, s);
      if (!rest.empty()) t += ", " + rest;
      if (!what.empty()) t += "  " + what;
      *out_ << t.substr(0, 79) << "\n" << std::flush;
      drawn_ = true;
    }
  }
}

void ProgressBar::done() {
  if (mode_ == Mode::terminal && drawn_) *out_ << "\r\x1b[K" << std::flush;
  drawn_ = false;
}

}  // namespace rb::app
