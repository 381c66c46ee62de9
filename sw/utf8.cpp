#include "utf8.h"

#include <nlohmann/json.hpp>

namespace rt {

std::string notUtf8(const std::string& text) {
    using json = nlohmann::json;
    try {
        (void)json(text).dump();  // (the check the report's writing would make)
        return {};
    } catch (const json::type_error&) {
        return json(text).dump(-1, ' ', false, json::error_handler_t::replace);
    }
}

}  // namespace rt
