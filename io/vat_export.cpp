#include "io/clip_writer_internal.h"
namespace softtouch::io::detail {
std::unique_ptr<ClipWriter> makeVatWriter(const ClipExportOptions&) { return nullptr; }
}
