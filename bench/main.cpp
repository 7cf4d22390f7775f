#include "suite.h"

int main(int argc, char** argv) { return imuconv::bench::Main(argc, argv); }
