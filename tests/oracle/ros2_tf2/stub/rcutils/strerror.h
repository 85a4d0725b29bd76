#pragma once
#include <cstring>
inline void rcutils_strerror(char* b, size_t n) { std::strncpy(b, "error", n); }
