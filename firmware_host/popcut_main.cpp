// Entry point of the popcut CLI; all behaviour lives in cli/.
#include "cli/commands.h"

int main(int argc, char** argv) { return popcut::cli::run(argc, argv); }
