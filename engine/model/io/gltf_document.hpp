/* gltf_document.hpp - the parsed glTF a texopt_model keeps so that saving can write the same
 * document back (model->document). Internal to engine/io.
 *
 * Holds the tinygltf model as loaded, with every image's original encoded bytes in
 * Image::image (as_is), the MIME type found by sniffing those bytes and their depth. Does not hold
 * decoded pixels (those are in texopt_model.images) and is never changed after loading:
 * saving works on a copy. Keeps the input of Sun et al. 2022 writable again; implements no
 * part of the method. */
#ifndef TEXOPT_GLTF_DOCUMENT_HPP
#define TEXOPT_GLTF_DOCUMENT_HPP

#include <string>
#include <vector>

#include <tiny_gltf.h>

struct texopt_gltf_document {
    tinygltf::Model gltf;
    std::vector<std::string> image_mime;       /* per image: "image/png", "image/jpeg", ... */
    std::vector<int> image_bits;               /* per image: bits per channel of the file (8, 16) */
    std::vector<char> image_chroma_subsampled; /* per image: a JPEG's colour planes below luma's resolution */
};

#endif
