// Flags from the rows of a parameter table (models/base/param.h): each
// row's value read by kind, checked against its range, its default shown as
// --help shows it. (Apart from rtsim_cli.cpp, which lists the flags.)
#pragma once

#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <string>
#include <type_traits>

#include "base/param.h"
#include "base/units.h"
#include "option_parsers.h"

namespace rt {

// Runs a parser of option_parsers.h, its error reported as CLI11's ("FLAG: what", exit 2).
template <class F>
auto cli(F&& f) -> decltype(f()) {
    try {
        return f();
    } catch (const OptionError& e) {
        throw CLI::ValidationError(e.flag, e.what());
    }
}

void addTime(CLI::App& app, const std::string& flag, Picos& target, const std::string& what, const std::string& group);

// A setting with two named values, kept as whether it is `on`; the value it
// holds now is the default, named first in the error for any other value.
// A choice of two names, or three where the row has a word ("auto": sets
// `chosenLater`, and the other two clear it).
void addChoice(CLI::App& app, const std::string& flag, bool& target, const std::string& on, const std::string& off,
               bool* chosenLater, const std::string& word, const std::string& what, const std::string& group);

// A rate's default as the flags write one ("1GB/s").
std::string rateText(double bps);

// A number (T: double or int) in [p.lo, p.hi] or p.word (held as p.wordValue).
template <class S, class T>
void addNumberOrWord(CLI::App& app, const Param<S>& p, T& target, const std::string& flag, const char* help,
                     const std::string& group) {
    const std::string word = p.word, range = formatNumber(p.lo) + ".." + formatNumber(p.hi);
    const double lo = p.lo, hi = p.hi;
    const T wordValue = T(p.wordValue);
    const std::string what = std::is_same_v<T, int> ? " or a whole number in " : " or a number in ";
    app.add_option_function<std::string>(flag, [=, &target](const std::string& v) {
           if (v == word) {
               target = wordValue;
               return;
           }
           T x = 0;  // (read as CLI11 reads the other numbers)
           if (!CLI::detail::lexical_cast(v, x) || !(x >= lo && x <= hi))
               throw CLI::ValidationError(flag, "expected " + word + what + range + ", got '" + v + "'");
           target = x == 0 ? 0 : x;  // (-0 is 0)
       }, help)
        ->default_str(target == wordValue ? word : formatNumber(target))
        ->group(group);
}

// The flag `flag` for row `p` of a parameter table (base/param.h), setting
// its field in `s`: its value read by kind, checked against its range.
template <class S>
void addParam(CLI::App& app, const Param<S>& p, S& s, const std::string& flag, const char* help, const std::string& group) {
    switch (p.kind) {
        case ParamKind::Time: addTime(app, flag, fieldOf<Picos>(p, s), help, group); return;
        case ParamKind::Rate: {
            double& f = fieldOf<double>(p, s);
            app.add_option_function<std::string>(flag, [flag, &f](const std::string& v) { f = cli([&] { return parseRateOf(flag, v); }); }, help)
                ->default_str(p.shown ? p.shown : rateText(f))->group(group);
            return;
        }
        case ParamKind::Count:
            if (p.word) {
                addNumberOrWord(app, p, fieldOf<int>(p, s), flag, help, group);
                return;
            }
            app.add_option(flag, fieldOf<int>(p, s), help)->check(CLI::Range(int(p.lo), int(p.hi)))->capture_default_str()->group(group);
            return;
        case ParamKind::Real: {
            if (p.word) {
                addNumberOrWord(app, p, fieldOf<double>(p, s), flag, help, group);
                return;
            }
            CLI::Option* o = app.add_option(flag, fieldOf<double>(p, s), help);
            if (std::isinf(p.hi)) {  // at least (or, open, above) lo, and finite
                const double lo = p.lo;
                const bool open = p.openBelow;
                char least[32];
                std::snprintf(least, sizeof least, "%g", lo);
                const std::string want = open ? "must be positive" : std::string("must be a finite number, at least ") + least;
                o->check(CLI::Validator([lo, open, want](std::string& v) {
                    char* end = nullptr;
                    const double x = std::strtod(v.c_str(), &end);
                    if (end == v.c_str() || *end) return std::string();  // (not a number: the conversion says so)
                    return std::isfinite(x) && (open ? x > lo : x >= lo) ? std::string() : want;
                }, open ? "" : "NONNEGATIVE", ""));
            } else {
                o->check(CLI::Range(p.lo, p.hi));
            }
            if (p.shown) o->default_str(p.shown);
            else o->capture_default_str();
            o->group(group);
            return;
        }
        case ParamKind::Choice:
            addChoice(app, flag, fieldOf<bool>(p, s), p.on, p.off, p.wordField ? &(s.*p.wordField) : nullptr,
                      p.word ? p.word : "", help, group);
            return;
        default: throw std::logic_error("parameter " + flag + ": not a value");
    }
}

}  // namespace rt
