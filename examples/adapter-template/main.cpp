// my-adapter: the standard adapter program (command line, adapter.json,
// logging, Ctrl-C) around the driver of machine_driver.hpp.
#include "machine_driver.hpp"

#include <nclink/run_adapter.hpp>

int main(int argc, char** argv) { return nclink::run_adapter(argc, argv, make_machine_driver()); }
