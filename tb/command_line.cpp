#include "command_line.h"

#include <algorithm>
#include <map>
#include <tuple>

#include "config_file.h"
#include "json_input.h"
#include "rtsim_cli.h"

namespace rt {
namespace {

// A throwaway parser of rtsim's flags: to look an option up, and to check
// one file's value alone.
struct Probe {
    RtsimOptions options;
    CLI::App app;
    Probe() { options.addTo(app); }
    CLI::Option* find(const std::string& name) {
        CLI::Option* o = app.get_option_no_throw("--" + name);
        return o ? o : app.get_option_no_throw("-" + name);
    }
};

// One line of a file as command-line arguments: a flag as --name=true
// (or false, or a count), a value as --name=value, a list as one argument
// joined by the option's delimiter (--light=1,2,3,4,5,6) or, for a
// repeatable flag, one --name=value per item.
std::vector<std::string> argsOf(const ConfigLine& line, CLI::Option& opt) {
    const std::string flag = "--" + line.name;
    if (opt.get_expected_min() == 0 || opt.get_type_size() == 0) {
        if (line.values.size() != 1) throw ConfigError(line.where + ": " + line.name + " is a flag: true or false, not a list");
        return {flag + "=" + line.values[0]};
    }
    if (line.values.size() == 1) return {flag + "=" + line.values[0]};
    if (opt.get_delimiter() != '\0') {
        std::string joined;
        for (size_t i = 0; i < line.values.size(); ++i) joined += (i ? std::string(1, opt.get_delimiter()) : "") + line.values[i];
        return {flag + "=" + joined};
    }
    if (opt.get_expected_max() <= 1)
        throw ConfigError(line.where + ": " + line.name + " takes one value, not a list of " + std::to_string(line.values.size()));
    std::vector<std::string> out;
    for (const std::string& v : line.values) out.push_back(flag + "=" + v);
    return out;
}

// The names the command line sets (parsed alone; if it does not parse,
// the real parse says why).
std::set<std::string> namesGiven(const std::vector<std::string>& rest) {
    std::set<std::string> names;
    Probe p;
    std::vector<std::string> args(rest.rbegin(), rest.rend());  // (CLI11 takes them reversed)
    try {
        p.app.parse(args);
    } catch (const CLI::Error&) {
    } catch (const std::exception&) {
    }
    for (const CLI::Option* o : p.app.get_options({}))
        if (o->count() > 0) names.insert(o->get_single_name());
    return names;
}

// Each line checked alone: a known flag, allowed here, with a value its
// parser takes. Returns its arguments; `name`, the flag's own name.
std::vector<std::string> checkedArgs(const ConfigLine& line, bool report, std::string& name, bool& repeatable) {
    Probe p;
    CLI::Option* opt = p.find(line.name);
    if (line.name.rfind('-', 0) == 0) {  // (a file names a flag without its dashes: "mesh = 4")
        const std::string bare = line.name.substr(std::min(line.name.find_first_not_of('-'), line.name.size()));
        const CLI::Option* named = bare.empty() ? nullptr : p.find(bare);
        throw ConfigError(line.where + ": '" + line.name + "': " +
                          (named ? "write the flag's long name without its dashes: '" + named->get_single_name() + " = ...'"
                                 : "no flag of that name (a file names a flag without its dashes, as in 'mesh = 4')"));
    }
    if (!opt || line.name == "help")
        throw ConfigError(line.where + ": no flag --" + line.name + " (rtsim --help lists them)");
    if (report && isOutputOrInternal(line.name))
        throw ConfigError(line.where + ": '" + line.name +
                          "': a report's flags never name an output, a program or an internal flag; give outputs on the command line");
    if (!opt->check_lname(line.name))  // (found as -q, not --q)
        throw ConfigError(line.where + ": '" + line.name + "' is the short -" + line.name +
                          ": a file names a flag by its long name, " + opt->get_single_name());
    if (line.name == "config" || line.name == "rerun")
        throw ConfigError(line.where + ": --" + line.name + " is read only from the command line");
    if (line.alone && opt->get_expected_min() > 0 && opt->get_type_size() != 0)  // (not a flag: the "true" is not the user's)
        throw ConfigError(line.where + ": " + line.name + " alone: it takes a value ('" + line.name + " = ...')");
    name = opt->get_single_name();
    repeatable = opt->get_expected_max() > 1 || opt->get_multi_option_policy() == CLI::MultiOptionPolicy::TakeAll;  // (rtsim --help: "...")
    const std::vector<std::string> args = argsOf(line, *opt);
    std::vector<std::string> reversed(args.rbegin(), args.rend());
    try {
        p.app.parse(reversed);
        p.options.checkAlone();
    } catch (const CLI::ParseError& e) {
        std::string value;
        for (const std::string& v : line.values) value += (value.empty() ? "" : ", ") + v;
        throw ConfigError(line.where + ": " + line.name + " = " + value + ": " + e.what());
    } catch (const std::exception& e) {
        throw ConfigError(line.where + ": " + line.name + ": " + e.what());
    }
    return args;
}

// Each setting checked once (checkedArgs): the same line again (a file of
// many lines) gives the same arguments. Each check parses with every flag
// of rtsim, so a long file of one setting took long (doc/history.md,
// "Figures behind the code's comments").
class LineChecks {
public:
    struct Checked {
        std::vector<std::string> args;
        std::string name;
        bool repeatable = false;
    };
    const Checked& of(const ConfigLine& line, bool report) {
        auto key = std::make_tuple(report, line.name, line.values);
        auto known = done_.find(key);
        if (known != done_.end()) return known->second;
        Checked c;
        c.args = checkedArgs(line, report, c.name, c.repeatable);
        return done_.emplace(std::move(key), std::move(c)).first->second;
    }

private:
    std::map<std::tuple<bool, std::string, std::vector<std::string>>, Checked> done_;
};

}  // namespace

std::vector<NamedFile> CommandLine::inputs(const RtsimOptions& o) const {
    std::vector<NamedFile> in;
    for (const std::string& c : configs) in.push_back({"--config", c, false});
    if (rerun) in.push_back({"--rerun", rerun->path, false});
    if (!o.scene.file.empty()) in.push_back({"--scene", o.scene.file, false});
    if (!o.boundariesFrom.empty()) in.push_back({"--boundaries-from", o.boundariesFrom, false});
    return in;
}

bool CommandLine::givesScene() const {
    for (const std::string& name : given)
        if (isSceneFlag(name)) return true;
    return false;
}

std::string CommandLine::originOf(const std::string& message) const {
    if (message.rfind("--", 0) != 0) return "";
    const size_t end = message.find_first_of(": =", 2);
    const auto it = where.find(message.substr(2, end == std::string::npos ? std::string::npos : end - 2));
    return it == where.end() ? "" : it->second + ": ";
}

CommandLine mergeFlags(const std::vector<ConfigSource>& sources, const std::vector<std::string>& rest, const std::string& argv0) {
    // Last value wins: a later line or file replaces a flag's whole value,
    // and the command line replaces them all; but a repeatable flag's lines
    // in one file are its list, in order (node-speed on two lines: both
    // nodes), which a later file replaces whole.
    // --mesh and --mesh-dims are one setting, the mesh's shape: the later
    // of a file's lines, and the command line's over a file's (a preset's
    // mesh-dims beat --mesh on the command line); both on the command line
    // are refused.
    CommandLine cl;
    cl.given = namesGiven(rest);
    if (cl.given.count("mesh") && cl.given.count("mesh-dims"))
        throw ConfigError("--mesh and --mesh-dims: both give the mesh's shape (--mesh-dims would win): give one");
    const auto otherShape = [](const std::string& n) { return n == "mesh" ? "mesh-dims" : n == "mesh-dims" ? "mesh" : ""; };
    std::vector<std::pair<std::string, std::vector<std::string>>> merged;  // in the order first named
    LineChecks checks;
    for (const ConfigSource& s : sources) {
        std::set<std::string> listed;  // repeatable flags this source has named
        for (const ConfigLine& line : s.lines) {
            const LineChecks::Checked& checked = checks.of(line, s.fromReport);
            const std::string& name = checked.name;
            const bool repeatable = checked.repeatable;
            std::vector<std::string> args = checked.args;
            if (const std::string other = otherShape(name); !other.empty()) {
                if (cl.given.count(other)) continue;  // the command line gives the shape the other way
                merged.erase(std::remove_if(merged.begin(), merged.end(), [&](const auto& m) { return m.first == other; }),
                             merged.end());
            }
            auto it = std::find_if(merged.begin(), merged.end(), [&](const auto& m) { return m.first == name; });
            if (it == merged.end()) merged.push_back({name, std::move(args)});
            else if (repeatable && listed.count(name)) it->second.insert(it->second.end(), args.begin(), args.end());
            else it->second = std::move(args);
            if (repeatable) listed.insert(name);
            cl.where[name] = line.where;
        }
    }
    cl.args = {argv0};
    for (const auto& [name, args] : merged) {
        if (cl.given.count(name)) {
            cl.where.erase(name);
            continue;
        }
        cl.args.insert(cl.args.end(), args.begin(), args.end());
    }
    cl.args.insert(cl.args.end(), rest.begin(), rest.end());
    return cl;
}

CommandLine assembleCommandLine(int argc, char** argv) {
    std::vector<std::string> rest, configs;
    std::optional<std::string> rerunPath;
    // --config FILE and --rerun FILE (or --config=FILE): the files' values.
    auto fileOf = [&](const std::string& flag, int& i) -> std::optional<std::string> {
        const std::string a = argv[i];
        if (a.rfind(flag + "=", 0) == 0) return a.substr(flag.size() + 1);
        if (a != flag) return std::nullopt;
        if (i + 1 >= argc) throw std::invalid_argument(flag + ": expected a file");
        return std::string(argv[++i]);
    };
    for (int i = 1; i < argc; ++i) {
        if (const auto c = fileOf("--config", i)) {
            configs.push_back(*c);
        } else if (const auto r = fileOf("--rerun", i)) {
            if (rerunPath) throw std::invalid_argument("--rerun: given twice");
            rerunPath = *r;
        } else {
            rest.push_back(argv[i]);
        }
    }
    checkNoEmptyValues(rest);
    if (rerunPath && !configs.empty())
        throw std::invalid_argument("--rerun: cannot be combined with --config (give the flags to change instead)");
    std::vector<ConfigSource> sources;
    std::optional<Rerun> rerun;
    if (rerunPath) {
        rerun = readRerun(*rerunPath);
        const std::string& flags = rerun->rerun["flags"].get_ref<const std::string&>();
        // (A config file's limit: a report may be far larger, and checking
        // each of a million lines alone would look like a hang.)
        if (flags.size() > kMaxConfigBytes)
            throw ConfigError("--rerun " + *rerunPath + ": rerun.flags: larger than " + std::to_string(kMaxConfigBytes) +
                              " bytes, a config file's limit (not rtsim's report)");
        sources.push_back({parseConfig(flags, "--rerun " + *rerunPath + ": rerun.flags"), true});
    }
    for (const std::string& c : configs) sources.push_back({readConfigFile(c), false});
    CommandLine cl = mergeFlags(sources, rest, argv[0]);
    cl.configs = configs;
    cl.rerun = std::move(rerun);
    // A flag that changes no frame (--no-baseline skips the reference runs
    // alone) is no what-if: the rerun is still checked against the report
    // (with it, an edited report's mesh ran unchecked).
    if (cl.rerun)
        for (const std::string& name : cl.given)
            if (!isOutputOrInternal(name) && name != "no-baseline") cl.rerun->overrides = true;
    return cl;
}

}  // namespace rt
