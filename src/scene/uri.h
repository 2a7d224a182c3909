// URI references of the files a glTF file names (buffers, images): what the
// importer decodes and the exporter writes, in one place.
#pragma once

#include <string>

namespace bounce::scene {

// A file name as a URI reference: RFC 3986's unreserved characters as they
// are, every other byte percent-encoded (a space is "%20").
std::string percentEncoded(const std::string& fileName);

// A URI reference's %XX escapes decoded to their bytes; a '%' not followed by
// two hex digits stays as it is.
std::string percentDecoded(const std::string& uri);

}  // namespace bounce::scene
