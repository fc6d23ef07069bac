#include "apps/report/report_record.hpp"

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <stdexcept>

namespace rb::app {

namespace {
// The record's format: raised when a measurement's shape changes, so that an old folder is refused
// whole rather than read in part.
constexpr int kRecordFormat = 1;

// FNV-1a, 64 bits, over the measurements' compact JSON (nlohmann orders keys and writes numbers the
// same way every time), as 16 hex digits.
std::string digest(const nlohmann::json& measurements) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (const unsigned char c : measurements.dump()) h = (h ^ c) * 0x100000001b3ull;
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}
}  // namespace

Record Record::replaying(const std::string& file) {
  std::ifstream f(file);
  if (!f) throw std::runtime_error(file + ": cannot be read (a folder written by `raybench report` holds it)");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(f);
  } catch (const nlohmann::json::exception& e) {  // a parse error, or a number beyond double
    throw std::runtime_error(file + ": not JSON (" + e.what() + ")");
  }
  if (!j.is_object() || !j.contains("measurements") || !j["measurements"].is_object())
    throw std::runtime_error(file + ": no \"measurements\" object: not a report's record");
  if (!j.contains("format") || j["format"] != kRecordFormat)
    throw std::runtime_error(file + ": a record of another format (this raybench reads format " + std::to_string(kRecordFormat) +
                             "): measure again with `raybench report`");
  if (!j.contains("digest") || j["digest"] != digest(j["measurements"]))
    throw std::runtime_error(file + ": its measurements do not match their digest (edited or damaged since the report wrote them)");
  Record r;
  r.kept_ = std::move(j["measurements"]);
  r.replay_ = true;
  r.file_ = file;
  return r;
}

nlohmann::json Record::document() const {
  return {{"raybench", "report record"}, {"format", kRecordFormat}, {"digest", digest(kept_)}, {"measurements", kept_}};
}

nlohmann::json Record::take(const std::string& name, const std::function<nlohmann::json()>& measure) {
  if (replay_) {
    const auto it = kept_.find(name);
    if (it == kept_.end())
      throw std::runtime_error(file_ + ": no measurement \"" + name + "\" (the report was written by another version of raybench, or "
                               "with other options)");
    return *it;
  }
  nlohmann::json j = measure();
  kept_[name] = j;
  return j;
}

}  // namespace rb::app
