// kincal: kinematic identification from the command line (cli/run.cpp).

#include "kincal/cli/run.hpp"

int main(int argc, char** argv) { return kincal::cli::run(argc, argv); }
