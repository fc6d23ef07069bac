// The query loop of `raybench query` (apps/cmd_query.cpp), without the command line: what the tests
// call. One JSON line out per line in; 1 if any line failed, with one line on `err` per failed
// input line.
#pragma once

#include <iosfwd>

namespace rb::app {

int run_query(std::istream& in, std::ostream& out, bool dbl);
int run_query(std::istream& in, std::ostream& out, std::ostream& err, bool dbl);

}  // namespace rb::app
