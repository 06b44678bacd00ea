#pragma once
// vx's own parameters in a PostgreSQL URI. libpq refuses query parameters it does not know, so a
// world opened by its name alone (the engine's WorldSource, the vx CLI, open_store) could not set
// the store's options; PgStore::open takes these out of the URI before libpq reads it.
//   vx_query_timeout_ms=N   PgStoreCreateInfo::query_timeout: N milliseconds, 1 to 3,600,000
// Thread affinity: any thread (pure functions).

#include <chrono>
#include <optional>
#include <string>
#include <string_view>

#include "world/base/result.h"

namespace vx::world {

inline constexpr std::string_view kQueryTimeoutParam = "vx_query_timeout_ms";
// The largest vx_query_timeout_ms (one hour): a longer one is a typo, not a wish to wait.
inline constexpr std::chrono::milliseconds kMaxUriQueryTimeout{3'600'000};

struct PgUriParams {
    std::string uri;                                        // Without vx's parameters: libpq's.
    std::optional<std::chrono::milliseconds> query_timeout; // vx_query_timeout_ms (the last given).
};

// Takes vx's parameters out of `uri` (a postgresql:// or postgres:// URI; any other string, a
// key=value one included, comes back unchanged). The error, one line, names the parameter and the
// value that is not a number of milliseconds in range.
Result<PgUriParams> split_pg_uri_params(std::string_view uri);

} // namespace vx::world
