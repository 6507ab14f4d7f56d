// 3MF (the 3D Manufacturing Format slicers open directly) through lib3mf (Debian's lib3mf-dev):
// one mesh object with one build item, in the units asked for. Only this file includes lib3mf.
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Model/COM/NMR_DLLInterfaces.h>

#include "frep/error.hpp"
#include "frep/mesh/mesh_io.hpp"

namespace frep {
namespace {

// Releases a lib3mf object when it goes out of scope.
struct Released {
  NMR::PLib3MFBase* p = nullptr;
  ~Released() {
    if (p) NMR::lib3mf_release(p);
  }
};

// Throws InputError naming `name` with lib3mf's own message when a call fails.
void check(LIB3MFRESULT r, NMR::PLib3MFBase* object, const std::string& name, const char* what) {
  if (r == LIB3MF_OK) return;
  DWORD code = 0;
  LPCSTR message = nullptr;
  if (object) NMR::lib3mf_getlasterror(object, &code, &message);
  throw InputError(name, 0, std::string(what) + ": " + (message && *message ? message : "lib3mf error " + std::to_string(r)));
}

DWORD unit_code(LengthUnit u) {
  switch (u) {
    case LengthUnit::Micron: return NMR::MODELUNIT_MICROMETER;
    case LengthUnit::Millimeter: return NMR::MODELUNIT_MILLIMETER;
    case LengthUnit::Centimeter: return NMR::MODELUNIT_CENTIMETER;
    case LengthUnit::Inch: return NMR::MODELUNIT_INCH;
    case LengthUnit::Foot: return NMR::MODELUNIT_FOOT;
    case LengthUnit::Meter: return NMR::MODELUNIT_METER;
  }
  return NMR::MODELUNIT_MILLIMETER;
}

}  // namespace

TriMesh as_3mf_stores(const TriMesh& mesh) {
  // lib3mf's own text conversion decides (six decimals, not always rounded to nearest): ask it.
  TriMesh m = read_3mf(write_3mf(mesh), mesh.name);
  m.name = mesh.name;
  return m;
}

std::string write_3mf(const TriMesh& m, LengthUnit units) {
  // 3MF stores single-precision coordinates and 32-bit indices.
  std::vector<NMR::MODELMESHVERTEX> vertices(m.vertices.size());
  for (std::size_t v = 0; v < m.vertices.size(); ++v)
    for (int c = 0; c < 3; ++c) {
      vertices[v].m_fPosition[c] = static_cast<float>(m.vertices[v][c]);
      if (!std::isfinite(vertices[v].m_fPosition[c]))
        throw InputError(m.name, 0, "vertex " + std::to_string(v) + " is beyond single precision, which 3MF stores; write OBJ or PLY");
    }
  std::vector<NMR::MODELMESHTRIANGLE> triangles(m.triangles.size());
  for (std::size_t t = 0; t < m.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) triangles[t].m_nIndices[k] = m.triangles[t][static_cast<std::size_t>(k)];

  Released model, object, item, writer;
  check(NMR::lib3mf_createmodel(&model.p), nullptr, m.name, "cannot create a 3MF model");
  check(NMR::lib3mf_model_setunit(model.p, unit_code(units)), model.p, m.name, "cannot set the 3MF units");
  check(NMR::lib3mf_model_addmeshobject(model.p, &object.p), model.p, m.name, "cannot add the 3MF mesh object");
  check(NMR::lib3mf_meshobject_setgeometry(object.p, vertices.data(), static_cast<DWORD>(vertices.size()),
                                            triangles.data(), static_cast<DWORD>(triangles.size())),
        object.p, m.name, "cannot store the mesh in 3MF");
  check(NMR::lib3mf_model_addbuilditem(model.p, object.p, nullptr, &item.p), model.p, m.name, "cannot add the 3MF build item");
  check(NMR::lib3mf_model_querywriter(model.p, "3mf", &writer.p), model.p, m.name, "cannot make a 3MF writer");
  ULONG64 size = 0;
  check(NMR::lib3mf_writer_getstreamsize(writer.p, &size), writer.p, m.name, "cannot size the 3MF file");
  std::string out(static_cast<std::size_t>(size), '\0');
  check(NMR::lib3mf_writer_writetobuffer(writer.p, reinterpret_cast<BYTE*>(out.data()), size), writer.p, m.name,
        "cannot write the 3MF file");
  return out;
}

TriMesh read_3mf(std::string_view bytes, const std::string& name) {
  Released model, reader, objects;
  check(NMR::lib3mf_createmodel(&model.p), nullptr, name, "cannot create a 3MF model");
  check(NMR::lib3mf_model_queryreader(model.p, "3mf", &reader.p), model.p, name, "cannot make a 3MF reader");
  std::string copy(bytes);  // lib3mf takes a non-const buffer
  check(NMR::lib3mf_reader_readfrombuffer(reader.p, reinterpret_cast<BYTE*>(copy.data()), copy.size()), reader.p, name,
        "not a readable 3MF file");
  TriMesh m;
  m.name = name;
  check(NMR::lib3mf_model_getmeshobjects(model.p, &objects.p), model.p, name, "cannot list the 3MF mesh objects");
  // Every mesh object, one after the other (their build transforms are not applied).
  for (;;) {
    BOOL more = false;
    check(NMR::lib3mf_resourceiterator_movenext(objects.p, &more), objects.p, name, "cannot list the 3MF mesh objects");
    if (!more) break;
    Released object;
    check(NMR::lib3mf_resourceiterator_getcurrent(objects.p, &object.p), objects.p, name, "cannot read a 3MF mesh object");
    DWORD nv = 0, nt = 0;
    check(NMR::lib3mf_meshobject_getvertexcount(object.p, &nv), object.p, name, "cannot read a 3MF mesh");
    check(NMR::lib3mf_meshobject_gettrianglecount(object.p, &nt), object.p, name, "cannot read a 3MF mesh");
    std::vector<NMR::MODELMESHVERTEX> vs(nv);
    std::vector<NMR::MODELMESHTRIANGLE> ts(nt);
    if (nv) check(NMR::lib3mf_meshobject_getvertices(object.p, vs.data(), nv, nullptr), object.p, name, "cannot read 3MF vertices");
    if (nt)
      check(NMR::lib3mf_meshobject_gettriangleindices(object.p, ts.data(), nt, nullptr), object.p, name, "cannot read 3MF triangles");
    const auto base = static_cast<std::uint32_t>(m.vertices.size());
    for (const auto& v : vs) m.vertices.push_back({v.m_fPosition[0], v.m_fPosition[1], v.m_fPosition[2]});
    for (const auto& t : ts) {
      for (DWORD i : t.m_nIndices)
        if (i >= nv) throw InputError(name, 0, "a 3MF triangle refers to vertex " + std::to_string(i) + " of " + std::to_string(nv));
      m.triangles.push_back({base + t.m_nIndices[0], base + t.m_nIndices[1], base + t.m_nIndices[2]});
    }
  }
  if (m.triangles.empty()) throw InputError(name, 0, "the 3MF file holds no mesh triangles");
  return m;
}

}  // namespace frep
