#include "tracer/kinds.hpp"

namespace rb::kinds {

const char* kind_name(Kind k) {
  const char* n = "?";
  AllKinds::each([&]<class K>() {
    if (K::id == k) n = K::name;
  });
  return n;
}

bool parse_kind(const std::string& name, Kind& k) {
  bool found = false;
  AllKinds::each([&]<class K>() {
    if (name == K::name) k = K::id, found = true;
  });
  return found;
}

std::array<std::size_t, kKinds> kind_counts(const Scene& s) {
  std::array<std::size_t, kKinds> c{};
  AllKinds::each([&]<class K>() { c[std::size_t(K::id)] = K::count(s); });
  return c;
}

}  // namespace rb::kinds
