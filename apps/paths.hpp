// Where raybench finds what it reads at run time besides its input: the chart scripts (tools/) and
// the embedded meshes (data/). An installed binary (cmake --install: PREFIX/bin/raybench) finds
// them in PREFIX/share/raybench, relative to its own path, so that it works from any folder; a
// binary in its build tree finds the source tree it was built from.
#pragma once

#include <string>

namespace rb::app {

// The folder holding tools/ and data/: $RAYBENCH_SHARE when set, else EXE/../share/raybench when it
// exists (an installed binary), else the source tree the binary was built from.
std::string share_dir();
std::string tool_path(const std::string& script);  // share_dir()/tools/SCRIPT
std::string data_dir();                             // share_dir()/data
std::string executable_path();                      // /proc/self/exe, "" when unknown
// A shell word: 'text' with single quotes escaped.
std::string shell_quote(const std::string& s);

}  // namespace rb::app
