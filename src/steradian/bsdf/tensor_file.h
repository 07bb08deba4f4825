#pragma once
/// The "tensor file" of Mitsuba and the RGL material database (the container of the .bsdf
/// files of Dupuy and Jakob 2018), as pbrt-v4 reads it. Little-endian:
///
///   12 bytes  "tensor_file\0"
///    2 bytes  version: major 1, minor 0
///    4 bytes  uint32 number of fields, then per field:
///      uint16 name length, the name's bytes, uint16 ndim, uint8 dtype (TensorDtype),
///      uint64 offset of the data from the start of the file, ndim x uint64 shape.
///
/// A field's data are its dtype's values in row-major order (the last index contiguous), at
/// its offset. The reader checks every size and offset against the file and reports any
/// violation as an sr::Error naming the file.
#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace sr {

/// pbrt-v4 / Mitsuba's type codes.
enum class TensorDtype : uint8_t {
    Invalid = 0,
    UInt8,
    Int8,
    UInt16,
    Int16,
    UInt32,
    Int32,
    UInt64,
    Int64,
    Float16,
    Float32,
    Float64,
};

/// Bytes per value of a dtype (0 for Invalid and unknown codes).
size_t tensor_dtype_size(TensorDtype t);
const char* to_string(TensorDtype t);

struct TensorField {
    TensorDtype dtype = TensorDtype::Invalid;
    std::vector<uint64_t> shape;
    std::string bytes;  ///< the data, shape product x dtype size bytes

    uint64_t count() const;
    /// The values of a Float32 field (converted from little-endian).
    std::vector<float> floats() const;
    /// "float32 [2, 3]"
    std::string describe() const;
};

struct TensorFile {
    std::map<std::string, TensorField> fields;
    const TensorField* find(const std::string& name) const {
        auto it = fields.find(name);
        return it == fields.end() ? nullptr : &it->second;
    }
};

/// Reads the fields of a tensor file from its contents. `name` (the file's path) prefixes
/// every error: "<name>: truncated tensor file: ...".
TensorFile parse_tensor_file(std::string_view bytes, std::string_view name);

/// The contents of a tensor file holding `file`'s fields (in the map's order, data after the
/// headers): what parse_tensor_file() reads back. For tests and tools that make inputs.
std::string write_tensor_file(const TensorFile& file);

/// A Float32 field of the given shape and values (row-major).
TensorField float32_field(std::vector<uint64_t> shape, const std::vector<float>& values);

}  // namespace sr
