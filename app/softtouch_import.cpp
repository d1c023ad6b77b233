// softtouch-import: reads one mesh or rig for softtouch, softtouch-cli and softtouch-bench, in its own process
// (io/import/isolated_import.h). Its request comes on stdin, its answer goes to stdout.
#include "io/import/isolated_import.h"

int main() { return softtouch::io::importerMain(); }
