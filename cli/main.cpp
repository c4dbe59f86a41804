// kincal: kinematic identification from the command line (cli/run.cpp).

#include "kincal/cli/run.hpp"

int main(int argc, char** argv) {
  kincal::cli::prepare_process();
  return kincal::cli::run(argc, argv);
}
