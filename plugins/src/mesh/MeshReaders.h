#pragma once
// OBJ, PLY (ASCII and binary), OFF and STL, each format read by a small strict reader of its own
// (ObjReader.cpp, PlyReader.cpp, OffReader.cpp, StlReader.cpp) from the file's bytes.
//
// Which reader, and why:
//  - OBJ, PLY and OFF went through OpenMesh's readers behind guards until bad input showed that
//    guarding them meant re-reading every token anyway: they turn values they cannot parse
//    ("nan", "1e39", "abc") into zeros or skip them, drop faces with unreadable or huge indices and
//    faces of 1-2 vertices, read a CR-only OBJ as empty, take a UTF-8 BOM as part of the first
//    statement, trust a PLY list count read from garbage (allocating gigabytes), load truncated
//    binary PLY partly, and their halfedge importer drops non-manifold faces. Visibility needs only
//    positions and polygons, so a strict reader of those few statements is smaller and safer than
//    the guards. No C or C++ PLY library is packaged for Debian, so PLY is read here too.
//  - STL is a trivial format (OpenMesh's reader dropped degenerate facets and accepted truncated
//    files as empty).
//
// Rules every reader follows:
//  - the file is checked (regular file, size limit; base/InputFile.h) before a byte is read,
//    then read whole; what is allocated grows with the data actually read, never with a count a
//    header declares, so memory stays a small multiple of the file's size;
//  - numbers are decimal, read by std::from_chars (locale-independent: a Qt program runs under the
//    user's LC_NUMERIC, where strtod may read "1,5"), finite and within float range. Hexadecimal
//    floats ("0x1p3") are refused: none of these formats defines them, and readers that accept
//    them (strtod) and readers that do not (streams) would see different geometry in one file;
//  - a text line ends at "\n", "\r\n" or a lone "\r"; a UTF-8 byte order mark at the start is
//    skipped;
//  - every polygon of 3 or more vertices is fan-triangulated and kept (degenerate and non-manifold
//    ones too: every triangle blocks rays); polygons of 1-2 vertices and anything unreadable are
//    refused with one line naming the file, the line (text) or element (binary), and the problem.

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include <glm/vec2.hpp>

#include "visibility/Scene.h"

namespace sightline::meshio {

/// What an OBJ says of its materials: the libraries it names (`mtllib`, as written); per triangle,
/// the index of the material in force (`usemtl`) in `names`, or -1 before any; its texture
/// coordinates (`vt`, as written: v up; not finite where unreadable) and per triangle its corners'
/// indices into them (-1 where a corner has none or names none read so far).
struct ObjMaterialUse {
    std::vector<std::string> libraries;
    std::vector<std::string> names;
    std::vector<int> triangleMaterial;
    std::vector<glm::dvec2> texCoords;
    std::vector<std::array<std::int32_t, 3>> triangleTexCoords;
};

/// Each reads a whole file's bytes (`what` names it in messages) into one mesh; throws
/// sightline::Error with one line on anything it does not accept.
Mesh readObj(std::string_view text, const std::string& what, std::vector<std::string>& warnings,
             ObjMaterialUse* materials = nullptr);
Mesh readPly(std::string_view text, const std::string& what);

Mesh readOff(std::string_view text, const std::string& what);
Mesh readStl(std::string_view bytes, const std::string& what);

/// A material of a library (.mtl), as far as albedos need it.
struct MtlMaterial {
    /// `Kd` (one value is grey); kUnknownAlbedo where there is none or it is not read.
    glm::vec3 diffuse = kUnknownAlbedo;
    bool diffuseGiven = false;        ///< a Kd statement was there (read or not)
    std::string texture;              ///< `map_Kd`'s file as written (the line's rest after its options); empty: none
    glm::dvec2 offset{0.0}, scale{1.0};   ///< map_Kd's -o and -s: (u, v) -> (u, v) * scale + offset
    bool clamp = false;               ///< map_Kd's -clamp on
};

/// A material library (.mtl) by material name. A Kd this reader does not take (spectral or xyz, a
/// value that is not a number in [0, 1]) leaves its material's diffuse colour unknown, with one
/// warning naming the first such line and their count; materials are lighting data that
/// visibility does not need, so nothing in a library refuses the level.
std::unordered_map<std::string, MtlMaterial> readMtl(std::string_view text, const std::string& what, std::vector<std::string>& warnings);

} // namespace sightline::meshio
