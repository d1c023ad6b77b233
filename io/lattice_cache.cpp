#include "io/clip_writer_internal.h"
namespace softtouch::io::detail {
std::unique_ptr<ClipWriter> makeLatticeCacheWriter() { return nullptr; }
}
