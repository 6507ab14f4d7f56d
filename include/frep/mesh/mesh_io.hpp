// Reading and writing triangle meshes: STL (ASCII and binary), OBJ, PLY (ASCII and binary), OFF,
// and 3MF (the 3D Manufacturing Format, through lib3mf).
//
// Readers never trust the file: every count is checked against the bytes that are actually
// there before anything is allocated, coordinates must be finite, and every problem is an
// InputError naming the file and the line (text) or byte offset (binary).
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "frep/mesh/mesh.hpp"

namespace frep {

enum class MeshFormat { Unknown, Stl, Obj, Ply, Off, ThreeMf };

// "stl", "obj", "ply", "off", "3mf".
const char* format_name(MeshFormat f);
// Format from the file name's extension (case-insensitive), Unknown if none matches.
MeshFormat format_from_extension(std::string_view path);
// Format from the first bytes of the file; Unknown if the content is not recognizable.
// Content wins over the extension: a file named .stl that starts with "ply" is read as PLY.
MeshFormat sniff_format(std::string_view bytes);

struct MeshReadOptions {
  MeshFormat format = MeshFormat::Unknown;  // Unknown: decide by content, then by extension
};

// Reads a mesh file. The result is as stored: vertices are not welded (see weld.hpp), polygons
// are fan-triangulated, triangles that repeat a vertex index are kept (validation reports them).
TriMesh read_mesh(const std::string& path, const MeshReadOptions& options = {});
// Same, from bytes in memory; `name` is used in messages (and for the extension fallback).
TriMesh read_mesh_from_memory(std::string_view bytes, const std::string& name,
                              const MeshReadOptions& options = {});

// Per-format readers over bytes in memory (the fuzz targets call these directly).
TriMesh read_stl(std::string_view bytes, const std::string& name);
TriMesh read_obj(std::string_view bytes, const std::string& name);
TriMesh read_ply(std::string_view bytes, const std::string& name);
TriMesh read_off(std::string_view bytes, const std::string& name);
// 3MF: every mesh object's triangles, in the file's units (their build transforms not applied).
TriMesh read_3mf(std::string_view bytes, const std::string& name);

// The length units a 3MF file states (other formats carry none).
enum class LengthUnit { Micron, Millimeter, Centimeter, Inch, Foot, Meter };
// "micron", "mm", "cm", "inch", "foot", "m" (also the long names); nullopt for anything else.
std::optional<LengthUnit> length_unit_from_name(std::string_view name);
// A 3MF file's bytes: one mesh object and one build item, in `units`. lib3mf writes coordinates
// with six decimals (a nanometre in millimetres): the file holds as_3mf_stores(mesh). Throws
// InputError for coordinates beyond single precision.
std::string write_3mf(const TriMesh& mesh, LengthUnit units = LengthUnit::Millimeter);
// The mesh as a 3MF file stores it (coordinates cut to six decimals by lib3mf's writer).
TriMesh as_3mf_stores(const TriMesh& mesh);

struct MeshWriteOptions {
  MeshFormat format = MeshFormat::Unknown;  // Unknown: from the output file's extension (a device: STL)
  bool ascii = false;                       // STL only: ASCII instead of binary
  LengthUnit units = LengthUnit::Millimeter;  // 3MF only: the units its coordinates are in
};

// Serializes a mesh (STL binary/ASCII, OBJ, binary little-endian PLY, 3MF).
std::string write_mesh_to_string(const TriMesh& mesh, MeshFormat format, bool ascii = false,
                                 LengthUnit units = LengthUnit::Millimeter);
// Writes a mesh file atomically (a device, is_device: binary STL, in place). Throws InputError for an
// unknown format or an unwritable path.
void write_mesh(const std::string& path, const TriMesh& mesh, const MeshWriteOptions& options = {});

}  // namespace frep
