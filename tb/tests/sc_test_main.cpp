// main() for the SystemC test executables: SystemC warnings and errors
// become exceptions, so a test that provokes one fails; the copyright banner
// is off. Each test runs in its own process (gtest_discover_tests), because
// SystemC elaborates only once per process.
#include <cstdlib>

#include <gtest/gtest.h>
#include <systemc>

int main(int argc, char** argv) {
    setenv("SYSTEMC_DISABLE_COPYRIGHT_MESSAGE", "1", 0);
    using namespace sc_core;
    sc_report_handler::set_actions(SC_WARNING, SC_THROW);
    sc_report_handler::set_actions(SC_ERROR, SC_THROW);
    sc_report_handler::set_actions("/OSCI/SystemC", SC_INFO, SC_DO_NOTHING);
    testing::InitGoogleTest(&argc, argv);
    return RUN_ALL_TESTS();
}

// libsystemc's own main() refers to sc_main; ours above is the one that runs.
int sc_main(int, char**) { return 1; }
