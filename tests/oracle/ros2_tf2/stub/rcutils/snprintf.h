#pragma once
#include <cstdio>
#define rcutils_snprintf std::snprintf
