#include "sdb/draco_decode.h"

#include <draco/compression/decode.h>
#include <draco/mesh/mesh.h>

#include <cstring>
#include <stdexcept>
#include <string>

namespace fly::sdb {

namespace {

// The Draco data type that stores exactly what a glTF integer componentType holds.
draco::DataType integerType(const DracoAttributeRequest& r) {
  switch (r.componentBytes) {
    case 1:
      return r.isSigned ? draco::DT_INT8 : draco::DT_UINT8;
    case 2:
      return r.isSigned ? draco::DT_INT16 : draco::DT_UINT16;
    default:
      return r.isSigned ? draco::DT_INT32 : draco::DT_UINT32;
  }
}

}  // namespace

DracoMesh decodeDracoMesh(std::span<const uint8_t> encoded,
                          const std::map<int, DracoAttributeRequest>& requests) {
  draco::DecoderBuffer buffer;
  buffer.Init(reinterpret_cast<const char*>(encoded.data()), encoded.size());
  draco::Decoder decoder;
  auto type = draco::Decoder::GetEncodedGeometryType(&buffer);
  if (!type.ok())
    throw std::runtime_error("it is not a Draco bit stream: " + type.status().error_msg_string());
  if (type.value() != draco::TRIANGULAR_MESH) {
    throw std::runtime_error("it holds a Draco point cloud, not a triangle mesh");
  }
  auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
  if (!decoded.ok())
    throw std::runtime_error("Draco cannot decode it: " + decoded.status().error_msg_string());
  const draco::Mesh& mesh = *decoded.value();

  DracoMesh out;
  out.pointCount = mesh.num_points();
  out.indices.reserve(size_t(mesh.num_faces()) * 3);
  for (draco::FaceIndex f(0); f < mesh.num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) out.indices.push_back(mesh.face(f)[k].value());
  }
  for (const auto& [id, request] : requests) {
    const draco::PointAttribute* a = mesh.GetAttributeByUniqueId(uint32_t(id));
    const std::string which = "Draco attribute " + std::to_string(id);
    if (!a) throw std::runtime_error(which + " is not in the compressed mesh");
    if (a->num_components() != request.components) {
      throw std::runtime_error(which + " has " + std::to_string(a->num_components()) +
                               " components but its accessor " + std::to_string(request.components));
    }
    const size_t valueBytes = size_t(request.components) * size_t(request.componentBytes);
    std::vector<uint8_t>& bytes = out.attributes[id];
    bytes.resize(out.pointCount * valueBytes);
    if (request.isFloat) {
      // Draco's own conversion to float (it dequantises and, for normalised integers, normalises).
      std::vector<float> value(size_t(request.components));
      for (draco::PointIndex p(0); p < mesh.num_points(); ++p) {
        if (!a->ConvertValue<float>(a->mapped_index(p), int8_t(request.components), value.data())) {
          throw std::runtime_error(which + " cannot be converted to floats");
        }
        std::memcpy(bytes.data() + p.value() * valueBytes, value.data(), valueBytes);
      }
    } else {
      if (a->data_type() != integerType(request)) {
        throw std::runtime_error(which + " holds another integer type than its accessor's componentType");
      }
      for (draco::PointIndex p(0); p < mesh.num_points(); ++p) {
        a->GetValue(a->mapped_index(p), bytes.data() + p.value() * valueBytes);
      }
    }
  }
  return out;
}

}  // namespace fly::sdb
