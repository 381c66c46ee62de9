#include "messages.h"

#include <cstdio>
#include <iostream>
#include <string>

#include <systemc>

namespace rt::msg {
namespace {

int verbosity = 0;
const char* programName = "rtsim";

// A message is one line: a control character in it (a value given with a
// newline, say) is written escaped.
std::string oneLine(const char* text) {
    std::string out;
    for (const char* c = text; *c; ++c) {
        const unsigned char u = static_cast<unsigned char>(*c);
        if (u >= 0x20 && u != 0x7f) out += *c;
        else if (u == '\n') out += "\\n";
        else if (u == '\t') out += "\\t";
        else if (u == '\r') out += "\\r";
        else {
            char hex[8];
            std::snprintf(hex, sizeof hex, "\\x%02x", u);
            out += hex;
        }
    }
    return out;
}

void handler(const sc_core::sc_report& r, const sc_core::sc_actions& actions) {
    const std::string id = r.get_msg_type();
    if (id.rfind("rtsim/", 0) != 0) {  // SystemC's own: its usual handling
        sc_core::sc_report_handler::default_handler(r, actions);
        return;
    }
    if (actions & sc_core::SC_DISPLAY) {
        const char* what = r.get_severity() == sc_core::SC_ERROR     ? "error: "
                           : r.get_severity() == sc_core::SC_WARNING ? "warning: "
                                                                     : "";
        std::cerr << programName << ": " << what << oneLine(r.get_msg()) << (verbosity > 0 ? " [" + id + "]" : std::string()) << "\n";
    }
}

}  // namespace

const char* program() { return programName; }
void setProgram(const char* name) { programName = name; }

void install(int verbose) {
    using namespace sc_core;
    verbosity = verbose;
    sc_report_handler::set_handler(handler);
    // Ours are shown and returned from; the caller decides what follows.
    for (const char* id : {kConfig, kScene, kOutput, kRun, kWatchdog, kSignal, kReference, kInfo}) {
        sc_report_handler::set_actions(id, SC_ERROR, SC_DISPLAY);
        sc_report_handler::set_actions(id, SC_WARNING, SC_DISPLAY);
        sc_report_handler::set_actions(id, SC_INFO, SC_DISPLAY);
    }
    sc_report_handler::set_verbosity_level(verbose >= 2 ? SC_DEBUG : verbose == 1 ? SC_MEDIUM : SC_LOW);
}

void error(const char* id, const std::string& text) { SC_REPORT_ERROR(id, text.c_str()); }
void warning(const char* id, const std::string& text) { SC_REPORT_WARNING(id, text.c_str()); }
void note(const char* id, const std::string& text) { SC_REPORT_INFO_VERB(id, text.c_str(), sc_core::SC_NONE); }
void info(const std::string& text) { SC_REPORT_INFO_VERB(kInfo, text.c_str(), sc_core::SC_MEDIUM); }

}  // namespace rt::msg
