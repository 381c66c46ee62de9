#include "config_file.h"

#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

namespace rt {
namespace {

bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\r'; }

std::string trim(const std::string& s) {
    size_t a = 0, b = s.size();
    while (a < b && isSpace(s[a])) ++a;
    while (b > a && isSpace(s[b - 1])) --b;
    return s.substr(a, b - a);
}

bool isNameChar(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_'; }

// One line's reader: a cursor over its text; errors name the line.
class LineReader {
public:
    LineReader(const std::string& text, std::string where) : s_(text), where_(std::move(where)) {}

    [[noreturn]] void fail(const std::string& why) const { throw ConfigError(where_ + ": " + why); }
    void skipSpace() {
        while (i_ < s_.size() && isSpace(s_[i_])) ++i_;
    }
    bool atEnd() {
        skipSpace();
        return i_ == s_.size() || s_[i_] == '#';  // (what follows is a comment)
    }
    char peek() { return i_ < s_.size() ? s_[i_] : '\0'; }
    void expect(char c) {
        skipSpace();
        if (peek() != c) fail(std::string("expected '") + c + "'");
        ++i_;
    }
    std::string name() {
        skipSpace();
        const size_t from = i_;
        while (i_ < s_.size() && isNameChar(s_[i_])) ++i_;
        if (i_ == from) fail("expected a flag's name (letters, digits, '-')");
        return s_.substr(from, i_ - from);
    }
    // A value: quoted, literal, or bare up to `stop` (end of line, or a
    // list's ',' and ']').
    std::string value(bool inList) {
        skipSpace();
        if (peek() == '"') return quoted();
        if (peek() == '\'') return literal();
        const size_t from = i_;
        while (i_ < s_.size() && !(inList && (s_[i_] == ',' || s_[i_] == ']')) &&
               !(s_[i_] == '#' && i_ > from && isSpace(s_[i_ - 1])))
            ++i_;
        const std::string v = trim(s_.substr(from, i_ - from));
        if (v.empty()) fail("no value");
        if (v.find_first_of("\"'[") != std::string::npos) fail("a quote or '[' inside a bare value: '" + v + "'");
        return v;
    }
    std::vector<std::string> list() {
        expect('[');
        std::vector<std::string> out;
        for (;;) {
            out.push_back(value(true));
            skipSpace();
            if (peek() == ']') break;
            if (peek() != ',') fail("expected ',' or ']' in the list (one line, closed by ']')");
            ++i_;
        }
        ++i_;
        return out;
    }

private:
    std::string quoted() {
        size_t j = i_ + 1;
        while (j < s_.size() && s_[j] != '"') j += s_[j] == '\\' ? 2 : 1;
        if (j >= s_.size()) fail("a string not closed by '\"'");
        try {
            std::string v = nlohmann::json::parse(s_.substr(i_, j + 1 - i_)).get<std::string>();
            i_ = j + 1;
            return v;
        } catch (const nlohmann::json::exception&) {
            fail("a string with an escape JSON does not know");
        }
    }
    std::string literal() {
        const size_t j = s_.find('\'', i_ + 1);
        if (j == std::string::npos) fail("a string not closed by \"'\"");
        std::string v = s_.substr(i_ + 1, j - i_ - 1);
        i_ = j + 1;
        return v;
    }

    const std::string& s_;
    std::string where_;
    size_t i_ = 0;
};

}  // namespace

std::vector<ConfigLine> parseConfig(const std::string& text, const std::string& origin) {
    std::vector<ConfigLine> out;
    // (A UTF-8 byte-order mark, as some editors save a file, is no part of its first line.)
    std::istringstream in(text.rfind("\xEF\xBB\xBF", 0) == 0 ? text.substr(3) : text);
    std::string raw;
    for (int n = 1; std::getline(in, raw); ++n) {
        const std::string where = origin + ":" + std::to_string(n);
        if (raw.find('\0') != std::string::npos) throw ConfigError(where + ": a NUL byte (not a text file)");
        const std::string line = trim(raw);
        if (line.empty() || line[0] == '#' || line[0] == ';') continue;
        if (line[0] == '[') throw ConfigError(where + ": sections ('" + line + "') are not read; one name = value per line");
        LineReader r(line, where);
        ConfigLine c;
        c.where = where;
        c.name = r.name();
        if (r.atEnd()) {
            c.values = {"true"};  // a flag alone
            c.alone = true;
        } else {
            r.expect('=');
            r.skipSpace();
            c.list = r.peek() == '[';
            c.values = c.list ? r.list() : std::vector<std::string>{r.value(false)};
            if (!r.atEnd()) r.fail("more after the value (a comment starts with ' #')");
        }
        out.push_back(std::move(c));
    }
    return out;
}

std::vector<ConfigLine> readConfigFile(const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) throw ConfigError("--config " + path + ": not a regular file");
    if (std::filesystem::file_size(path, ec) > kMaxConfigBytes || ec)
        throw ConfigError("--config " + path + ": larger than " + std::to_string(kMaxConfigBytes) + " bytes (not a config file)");
    std::ifstream f(path, std::ios::binary);
    if (!f) throw ConfigError("--config " + path + ": cannot be read");
    std::ostringstream text;
    text << f.rdbuf();
    return parseConfig(text.str(), path);
}

std::string configValue(const std::string& v) {
    if (v == "true" || v == "false" || v == "nan" || v == "inf") return v;
    if (!v.empty() && v.compare(0, 2, "0x") != 0 && v.compare(0, 2, "0X") != 0 && !isSpace(v[0]) && !isSpace(v.back())) {
        char* end = nullptr;
        std::strtod(v.c_str(), &end);
        if (end == v.c_str() + v.size()) return v;
    }
    if (v.size() == 1 && v != "'") return "'" + v + "'";
    return nlohmann::json(v).dump();
}

std::string configLine(const std::string& name, const std::vector<std::string>& values) {
    if (values.size() == 1) return name + "=" + configValue(values[0]);
    std::string line = name + "=[";
    for (size_t i = 0; i < values.size(); ++i) line += (i ? ", " : "") + configValue(values[i]);
    return line + "]";
}

bool isOutputOrInternal(const std::string& name) {
    for (const char* o : {"image", "report", "vcd", "quiet", "verbose", "map", "config", "rerun", "as-baseline",
                          "as-comparison", "help"})
        if (name == o) return true;
    return false;
}

}  // namespace rt
