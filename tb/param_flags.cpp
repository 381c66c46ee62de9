#include "param_flags.h"

#include <algorithm>

namespace rt {

void addTime(CLI::App& app, const std::string& flag, Picos& target, const std::string& what, const std::string& group) {
    app.add_option_function<std::string>(flag, [flag, &target](const std::string& s) { target = cli([&] { return parseTimeOf(flag, s); }); }, what)
        ->default_str(formatTime(target))
        ->group(group);
}

void addChoice(CLI::App& app, const std::string& flag, bool& target, const std::string& on, const std::string& off,
               bool* chosenLater, const std::string& word, const std::string& what, const std::string& group) {
    const std::string given = chosenLater && *chosenLater ? word : target ? on : off;
    const std::string names = chosenLater ? word + ", " + off + " or " + on : given + " or " + (target ? off : on);
    app.add_option_function<std::string>(flag, [flag, &target, on, off, chosenLater, word, names](const std::string& s) {
           if (chosenLater && s == word) {  // (and not a value given before it: the last one given counts)
               *chosenLater = true;
               target = false;
               return;
           }
           if (s != on && s != off) throw CLI::ValidationError(flag, "expected " + names + ", got '" + s + "'");
           target = s == on;
           if (chosenLater) *chosenLater = false;
       }, what)
        ->default_str(given)
        ->group(group);
}

std::string rateText(double bps) {
    std::string s = formatRate(bps);
    s.erase(std::remove(s.begin(), s.end(), ' '), s.end());
    return s;
}

}  // namespace rt
