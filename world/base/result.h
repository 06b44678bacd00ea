#pragma once
// A value or an error message: how recoverable failures (I/O, corrupt data, bad input) reach
// callers. The types are public (the facade returns them), so they live in include/vx/result.h.

#include <vx/result.h>

#include "world/base/assert.h"
