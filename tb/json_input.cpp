#include "json_input.h"

#include <filesystem>
#include <fstream>
#include <sstream>

namespace rt {
namespace {

using json = nlohmann::json;

template <class Input>
json parseLimited(Input&& in, const std::string& origin) {
    // The parser builds the tree without recursion; the callback stops it
    // at the first value nested too deep, before anything recursive (a
    // comparison, a dump, a destructor) ever sees one.
    const json::parser_callback_t depthLimit = [&origin](int depth, json::parse_event_t, json&) {
        if (depth >= kMaxJsonDepth)  // (depth counts from 0)
            throw JsonInputError(origin + ": nested more than " + std::to_string(kMaxJsonDepth) + " deep (not a report)");
        return true;
    };
    try {
        return json::parse(std::forward<Input>(in), depthLimit);
    } catch (const json::parse_error& e) {
        throw JsonInputError(origin + ": not JSON (at byte " + std::to_string(e.byte) + ")");
    } catch (const json::out_of_range&) {
        // A number past a double's range (1e999) is valid JSON syntax that
        // the parser refuses with another exception (found by fuzz_report).
        throw JsonInputError(origin + ": a number too large for a double (not a report)");
    }
}

std::string typeName(json::value_t t) {
    switch (t) {
        case json::value_t::object: return "an object";
        case json::value_t::array: return "a list";
        case json::value_t::string: return "a string";
        case json::value_t::boolean: return "true or false";
        case json::value_t::number_integer:
        case json::value_t::number_unsigned: return "an integer";
        case json::value_t::number_float: return "a number";
        case json::value_t::null: return "null";
        default: return "something else";
    }
}

const json* find(const json& j, const std::string& path) {
    const json* at = &j;
    std::istringstream parts(path);
    for (std::string key; std::getline(parts, key, '.');) {
        if (!at->is_object()) return nullptr;
        const auto it = at->find(key);
        if (it == at->end()) return nullptr;
        at = &*it;
    }
    return at;
}

}  // namespace

json readJsonFile(const std::string& path, uintmax_t maxBytes) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) throw JsonInputError(path + ": not a regular file");
    const uintmax_t size = std::filesystem::file_size(path, ec);
    if (ec || size > maxBytes) throw JsonInputError(path + ": larger than " + std::to_string(maxBytes) + " bytes");
    std::ifstream f(path, std::ios::binary);
    if (!f) throw JsonInputError(path + ": cannot be read");
    return parseLimited(f, path);
}

json parseJsonText(const std::string& text, const std::string& origin) { return parseLimited(text, origin); }

const json& jsonField(const json& j, const std::string& path, json::value_t type, const std::string& origin) {
    const json* f = find(j, path);
    if (!f) throw JsonInputError(origin + ": " + path + ": missing");
    const bool number = type == json::value_t::number_float || type == json::value_t::number_integer;
    const bool ok = number ? (type == json::value_t::number_float ? f->is_number() : f->is_number_integer())
                           : f->type() == type;
    if (!ok) throw JsonInputError(origin + ": " + path + ": expected " + typeName(type) + ", got " + typeName(f->type()));
    return *f;
}

bool hasJsonField(const json& j, const std::string& path) { return find(j, path) != nullptr; }

}  // namespace rt
