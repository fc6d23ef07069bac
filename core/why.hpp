// The builders' error convention (docs/DESIGN.md section 7): degenerate or invalid geometric input
// gives P::never(), a primitive no ray hits; a caller that wants the reason passes the optional
// last argument `std::string* why` of the builder, which receives one line when the result is
// never() and is left alone otherwise.
#pragma once

#include <string>
#include <string_view>

namespace rb {

inline void tell_why(std::string* why, std::string_view reason) {
  if (why) *why = std::string(reason);
}

// P::never() after telling why.
template <class P>
inline P never_because(std::string* why, std::string_view reason) {
  tell_why(why, reason);
  return P::never();
}

}  // namespace rb
