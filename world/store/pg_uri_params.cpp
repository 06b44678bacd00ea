#include "world/store/pg_uri_params.h"

#include <charconv>
#include <cstdint>

#include "world/store/pg_store.h"

namespace vx::world {

namespace {

// Digits only (no sign, no spaces, no percent-encoding), 1 to kMaxUriQueryTimeout.
Result<std::chrono::milliseconds> parse_timeout(std::string_view value) {
    uint64_t ms = 0;
    const char* end = value.data() + value.size();
    const auto [ptr, ec] = std::from_chars(value.data(), end, ms);
    const bool digits = !value.empty() && value.find_first_not_of("0123456789") == std::string_view::npos;
    if (!digits || ec != std::errc{} || ptr != end || ms == 0 || ms > uint64_t(kMaxUriQueryTimeout.count()))
        return Error{std::string(kQueryTimeoutParam) + " must be a whole number of milliseconds from 1 to " +
                     std::to_string(kMaxUriQueryTimeout.count()) + ", not '" + std::string(value) + "'"};
    return std::chrono::milliseconds(int64_t(ms));
}

} // namespace

Result<PgUriParams> split_pg_uri_params(std::string_view uri) {
    PgUriParams out;
    const size_t query = is_pg_uri(uri) ? uri.find('?', uri.find("://") + 3) : std::string_view::npos;
    if (query == std::string_view::npos) {
        out.uri = uri;
        return out;
    }
    out.uri = uri.substr(0, query);
    char sep = '?';
    for (size_t p = query + 1; p <= uri.size();) {
        const size_t end = std::min(uri.find('&', p), uri.size());
        const std::string_view param = uri.substr(p, end - p);
        const size_t eq = param.find('=');
        if (param.substr(0, eq) == kQueryTimeoutParam) {
            auto timeout = parse_timeout(eq == std::string_view::npos ? std::string_view{} : param.substr(eq + 1));
            if (!timeout)
                return Error{timeout.error()};
            out.query_timeout = *timeout;
        } else {
            out.uri += sep;
            out.uri += param;
            sep = '&';
        }
        p = end + 1;
    }
    return out;
}

} // namespace vx::world
