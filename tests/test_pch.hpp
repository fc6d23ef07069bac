// The headers every test executable of the `debug` preset parses: precompiled once (tests/CMakeLists.txt)
// instead of once per test file. Only headers, no test code: what a test file uses it still includes
// itself, so each file also compiles without this header.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <functional>
#include <limits>
#include <map>
#include <random>
#include <regex>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/counted.hpp"
#include "core/ray.hpp"
#include "core/vec3.hpp"
#include "kernels/box.hpp"
#include "kernels/cylinder_cone.hpp"
#include "kernels/plane.hpp"
#include "kernels/polyhedron.hpp"
#include "kernels/quadric.hpp"
#include "kernels/sphere.hpp"
#include "kernels/torus.hpp"
#include "kernels/triangle.hpp"
#include "kernels/triangle_woop.hpp"
#include "scene/loaders.hpp"
#include "scene/sources.hpp"
#include "soa/prims.hpp"
#include "soa/rays.hpp"
#include "kernel_test_util.hpp"
