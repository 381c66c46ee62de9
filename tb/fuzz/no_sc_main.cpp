// libsystemc.so wants an sc_main (declared extern "C" by <systemc>); the
// fuzz targets of the report and config readers link the testbench's
// library but elaborate no machine.
extern "C" int sc_main(int, char**) { return 0; }
