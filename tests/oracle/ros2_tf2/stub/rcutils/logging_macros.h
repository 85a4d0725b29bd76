#pragma once
#include <cstdio>
#define RCUTILS_LOG_ERROR(...) (std::fprintf(stderr, __VA_ARGS__), std::fputc('\n', stderr))
#define RCUTILS_LOG_WARN(...) (std::fprintf(stderr, __VA_ARGS__), std::fputc('\n', stderr))
#define RCUTILS_LOG_DEBUG(...) ((void)0)
#define RCUTILS_LOG_INFO(...) ((void)0)
#define RCUTILS_LOG_WARN_THROTTLE(a, b, ...) (std::fprintf(stderr, __VA_ARGS__), std::fputc('\n', stderr))
#define RCUTILS_STEADY_TIME 0
