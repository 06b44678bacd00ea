#pragma once
// Minimal logging to stderr. Thread-safe (each call is one fprintf).

#include <cstdio>

#define VX_LOG_ERROR(...) (std::fprintf(stderr, "vx error: " __VA_ARGS__), std::fputc('\n', stderr))
#define VX_LOG_WARN(...) (std::fprintf(stderr, "vx warning: " __VA_ARGS__), std::fputc('\n', stderr))
