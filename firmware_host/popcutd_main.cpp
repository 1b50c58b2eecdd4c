// Entry point of popcutd, the job-queue daemon; all behaviour lives in daemon/.
#include "daemon/popcutd.h"

int main(int argc, char** argv) { return popcut::daemon::run_popcutd(argc, argv); }
