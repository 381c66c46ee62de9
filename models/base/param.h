// A parameter of the machine, declared once beside the field it sets (as
// gem5's Param.X(default, "what")): its name, kind and unit, range, what
// it means, and where the report's config echoes it. From these tables
// rtsim makes its command line and config files (the flags, their checks
// and --help, so doc/usage.md), the report's `config`, the names of
// --node-cost and the keys of --link-set; the default is the field's
// initial value. Tables: costParams() and machineParams()
// (config/machine_config.h), linkParams() (channel/link_params.h),
// balanceParams() (config/machine_config.h).
//
// A row of kind Special is a flag with a syntax of its own (a mesh shape,
// a policy's name, a list of per-node settings): the table gives its name,
// group and help, and tb/rtsim_cli.cpp reads it. A row of kind Part stands
// for another table's rows, in its place.
#pragma once
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <variant>

#include "base/units.h"

namespace rt {

enum class ParamKind {
    Time,     // a time with a unit ("20ns"); echoed in ns
    Rate,     // bytes per second with a unit ("1GB/s")
    Count,    // a whole number in [lo, hi]
    Real,     // a number in [lo, hi] (hi infinite: at least lo; lo > 0 with open: above lo)
    Choice,   // one of two names: `on` sets the field true (or a third, `word`: sets wordField, chosen later)
    Special,  // read by the command line itself (tb/rtsim_cli.cpp)
    Part,     // another table's rows here (`part` names it)
};

template <class S>
struct Param {
    using Field = std::variant<std::monostate, Picos S::*, double S::*, int S::*, bool S::*, Picos& (*)(S&)>;
    const char* name;          // the flag without "--" (in a part: after its prefix)
    ParamKind kind;
    const char* help;
    Field field{};
    const char* echo = nullptr;  // JSON pointer into the config echo (of the struct's object); nullptr: none here
    double lo = 0, hi = std::numeric_limits<double>::infinity();
    bool openBelow = false;      // Real: lo itself is refused ("must be positive")
    const char* on = nullptr;    // Choice: the two names, `on` for true
    const char* off = nullptr;
    const char* shown = nullptr;  // --help's default, if not the field's value
    const char* group = nullptr;  // --help's group (a part's rows take their Part row's)
    const char* portHelp = nullptr;  // link settings: the frame-buffer ports' --fb-NAME, if they have it
    const char* part = nullptr;   // Part: "costs", "link", "fb-port" or "balance"
    const char* word = nullptr;   // Real, Count: a word it also takes, for the value wordValue (outside [lo, hi]); Choice: a third name
    double wordValue = 0;
    bool S::*wordField = nullptr;  // Choice: set by `word` (and cleared by the other two)
};

// The rows, by kind. `group` is --help's group (nullptr in a part's table:
// its Part row's).
template <class S, class F>
Param<S> timeParam(const char* name, F S::*field, const char* echo, const char* help, const char* group = nullptr) {
    Param<S> p{name, ParamKind::Time, help, field, echo};
    p.group = group;
    return p;
}
template <class S>
Param<S> timeParamAt(const char* name, Picos& (*field)(S&), const char* echo, const char* help) {
    return Param<S>{name, ParamKind::Time, help, field, echo};
}
template <class S>
Param<S> rateParam(const char* name, double S::*field, const char* echo, const char* help, const char* group = nullptr) {
    Param<S> p{name, ParamKind::Rate, help, field, echo};
    p.group = group;
    return p;
}
// The same row with `help` for the frame-buffer ports (link settings).
template <class S>
Param<S> alsoForPorts(Param<S> p, const char* help) {
    p.portHelp = help;
    return p;
}
// The same row with --help's default given in words.
template <class S>
Param<S> shownAs(Param<S> p, const char* shown) {
    p.shown = shown;
    return p;
}
// The same Real or Count row taking `word` too, held as `value` (outside its range:
// "auto", chosen where the row's field is used).
template <class S>
Param<S> orWord(Param<S> p, const char* word, double value) {
    p.word = word;
    p.wordValue = value;
    return p;
}
// The same Choice row taking a third name, `word` ("auto"), which sets
// `field` instead (the choice made where it is used, as the row's own
// field then holds it).
template <class S>
Param<S> orWord(Param<S> p, const char* word, bool S::*field) {
    p.word = word;
    p.wordField = field;
    return p;
}
// The same Real row refusing its lower bound itself.
template <class S>
Param<S> above(Param<S> p) {
    p.openBelow = true;
    return p;
}
template <class S, class F>
Param<S> numberParam(const char* name, F S::*field, double lo, double hi, const char* echo, const char* help,
                     const char* group = nullptr) {
    Param<S> p{name, std::is_same_v<F, int> ? ParamKind::Count : ParamKind::Real, help, field, echo, lo, hi};
    p.group = group;
    return p;
}
template <class S>
Param<S> choiceParam(const char* name, bool S::*field, const char* on, const char* off, const char* echo,
                     const char* help, const char* group = nullptr) {
    Param<S> p{name, ParamKind::Choice, help, field, echo};
    p.on = on;
    p.off = off;
    p.group = group;
    return p;
}
template <class S>
Param<S> specialParam(const char* name, const char* help, const char* group = nullptr) {
    Param<S> p{name, ParamKind::Special, help};
    p.group = group;
    return p;
}
template <class S>
Param<S> partParam(const char* part, const char* group) {
    Param<S> p{part, ParamKind::Part, ""};
    p.part = part;
    p.group = group;
    return p;
}

// The field of row `p` in `s`, of type T (the row's kind says which).
template <class T, class S>
T& fieldOf(const Param<S>& p, S& s) {
    if (auto* f = std::get_if<T S::*>(&p.field)) return s.**f;
    if constexpr (std::is_same_v<T, Picos>)
        if (auto* f = std::get_if<Picos& (*)(S&)>(&p.field)) return (*f)(s);
    throw std::logic_error(std::string("parameter ") + p.name + ": no field of that type");
}
template <class T, class S>
T fieldOf(const Param<S>& p, const S& s) {
    return fieldOf<T>(p, const_cast<S&>(s));
}

}  // namespace rt
