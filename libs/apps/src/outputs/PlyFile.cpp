// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/apps/PlyFile.h>
#include <emslam/io/AtomicFile.h>
#include <emslam/io/OutputFile.h>

#include <mrpt/core/format.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace emslam::apps
{
void savePly(const emslam::slam::IntensityCloud& cloud, const std::string& file)
{
    emslam::io::writeFileAtomically(
        file,
        [&](const std::string& partial)
        {
            emslam::io::OutputFile f(partial, file);
            auto& out = f.text();
            out << "ply\nformat binary_little_endian 1.0\ncomment emslam map\nelement vertex "
                << cloud.size()
                << "\nproperty float x\nproperty float y\nproperty float z\n"
                   "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n";
            for (std::size_t i = 0; i < cloud.size(); ++i)
            {
                const auto& p = cloud.points[i];
                const float xyz[3] = {p.x, p.y, p.z};
                const std::uint8_t g = cloud.intensity[i];
                const std::uint8_t rgb[3] = {g, g, g};
                f.put(xyz, sizeof(xyz));
                f.put(rgb, sizeof(rgb));
            }
            f.close();
            return true;
        });
}

void saveReferencePly(const emslam::eval::ReferenceSurface& surface, const std::string& file)
{
    const auto& s = surface;
    if (s.normals.size() != s.points.size() || s.seen_range.size() != s.points.size())
    {
        throw std::invalid_argument("saveReferencePly: every point needs a normal and a range");
    }
    emslam::io::writeFileAtomically(
        file,
        [&](const std::string& partial)
        {
            emslam::io::OutputFile f(partial, file);
            f.text() << "ply\nformat binary_little_endian 1.0\ncomment emslam true surfaces\n"
                     << "comment sample_spacing " << mrpt::format("%.9g", s.spacing)
                     << "\nelement vertex " << s.points.size()
                     << "\nproperty float x\nproperty float y\nproperty float z\n"
                        "property float nx\nproperty float ny\nproperty float nz\n"
                        "property float seen_range\nend_header\n";
            for (std::size_t i = 0; i < s.points.size(); ++i)
            {
                const auto& p = s.points[i];
                const auto& n = s.normals[i];
                const float v[7] = {p.x, p.y, p.z, n.x, n.y, n.z, s.seen_range[i]};
                f.put(v, sizeof(v));
            }
            f.close();
            return true;
        });
}

namespace
{
/** One scalar property of the vertex element. */
struct PlyProperty
{
    std::string name;
    std::size_t bytes{0};
    char kind{'f'};  // 'f' float, 'i' signed, 'u' unsigned
};

/** What the header says. */
struct PlyHeader
{
    bool binary{false};
    std::size_t vertices{0};
    std::vector<PlyProperty> properties;
    double spacing{0};
};

PlyProperty scalarType(const std::string& type, const std::string& name)
{
    static const std::map<std::string, std::pair<std::size_t, char>> types = {
        {"char", {1, 'i'}},  {"int8", {1, 'i'}},    {"uchar", {1, 'u'}},  {"uint8", {1, 'u'}},
        {"short", {2, 'i'}}, {"int16", {2, 'i'}},   {"ushort", {2, 'u'}}, {"uint16", {2, 'u'}},
        {"int", {4, 'i'}},   {"int32", {4, 'i'}},   {"uint", {4, 'u'}},   {"uint32", {4, 'u'}},
        {"float", {4, 'f'}}, {"float32", {4, 'f'}}, {"double", {8, 'f'}}, {"float64", {8, 'f'}}};
    const auto it = types.find(type);
    if (it == types.end())
    {
        throw std::runtime_error("unknown property type '" + type + "'");
    }
    return {name, it->second.first, it->second.second};
}

/** Parses the header up to end_header; the vertex element must come first. */
PlyHeader readHeader(std::istream& in)
{
    std::string line;
    if (!std::getline(in, line) || line.rfind("ply", 0) != 0)
    {
        throw std::runtime_error("not a PLY file (no 'ply' first line)");
    }
    PlyHeader h;
    bool in_vertex = false, seen_vertex = false;
    while (std::getline(in, line))
    {
        std::istringstream words(line);
        std::string w;
        words >> w;
        if (w == "end_header")
        {
            return h;
        }
        if (w == "format")
        {
            std::string f;
            words >> f;
            if (f != "ascii" && f != "binary_little_endian")
            {
                throw std::runtime_error("unsupported PLY format '" + f + "'");
            }
            h.binary = f != "ascii";
        }
        else if (w == "comment")
        {
            std::string key;
            if (words >> key && key == "sample_spacing")
            {
                words >> h.spacing;
            }
        }
        else if (w == "element")
        {
            std::string name;
            words >> name;
            in_vertex = name == "vertex";
            if (in_vertex)
            {
                words >> h.vertices;
                seen_vertex = true;
            }
            else if (!seen_vertex)
            {
                throw std::runtime_error("the element '" + name + "' comes before the vertices");
            }
        }
        else if (w == "property" && in_vertex)
        {
            std::string type, name;
            words >> type >> name;
            if (type == "list")
            {
                throw std::runtime_error("a list property in the vertex element");
            }
            h.properties.push_back(scalarType(type, name));
        }
    }
    throw std::runtime_error("no end_header line");
}

double binaryValue(const char* p, const PlyProperty& prop)
{
    switch (prop.kind)
    {
        case 'f':
        {
            if (prop.bytes == 4)
            {
                float v;
                std::memcpy(&v, p, 4);
                return v;
            }
            double v;
            std::memcpy(&v, p, 8);
            return v;
        }
        case 'i':
        {
            std::int64_t v = 0;
            std::memcpy(&v, p, prop.bytes);
            const int shift = static_cast<int>(64 - 8 * prop.bytes);
            return static_cast<double>(
                static_cast<std::int64_t>(static_cast<std::uint64_t>(v) << shift) >>
                shift);  // sign-extend
        }
        default:
        {
            std::uint64_t v = 0;
            std::memcpy(&v, p, prop.bytes);
            return static_cast<double>(v);
        }
    }
}

/** Reads the values of one vertex into `values` (one per property). */
void readVertex(std::istream& in, const PlyHeader& h, std::vector<double>& values)
{
    if (!h.binary)
    {
        for (auto& v : values)
        {
            if (!(in >> v))
            {
                throw std::runtime_error("a vertex line is short or holds a bad number");
            }
        }
        return;
    }
    char buf[8];
    for (std::size_t k = 0; k < values.size(); ++k)
    {
        if (!in.read(buf, static_cast<std::streamsize>(h.properties[k].bytes)))
        {
            throw std::runtime_error("the vertex data is truncated");
        }
        values[k] = binaryValue(buf, h.properties[k]);
    }
}

int column(const PlyHeader& h, const std::string& name)
{
    for (std::size_t k = 0; k < h.properties.size(); ++k)
    {
        if (h.properties[k].name == name)
        {
            return static_cast<int>(k);
        }
    }
    return -1;
}

emslam::eval::ReferenceSurface readVertices(std::istream& in, const PlyHeader& h)
{
    const int x = column(h, "x"), y = column(h, "y"), z = column(h, "z");
    const int nx = column(h, "nx"), ny = column(h, "ny"), nz = column(h, "nz");
    const int range = column(h, "seen_range");
    if (x < 0 || y < 0 || z < 0)
    {
        throw std::runtime_error("the vertices have no x, y, z");
    }
    const bool normals = nx >= 0 && ny >= 0 && nz >= 0;
    emslam::eval::ReferenceSurface s;
    s.spacing = h.spacing;
    std::vector<double> v(h.properties.size());
    const auto at = [&v](int k) { return static_cast<float>(v[static_cast<std::size_t>(k)]); };
    for (std::size_t i = 0; i < h.vertices; ++i)
    {
        readVertex(in, h, v);
        s.points.emplace_back(at(x), at(y), at(z));
        if (normals)
        {
            s.normals.emplace_back(at(nx), at(ny), at(nz));
        }
        if (range >= 0)
        {
            s.seen_range.push_back(at(range));
        }
    }
    return s;
}
}  // namespace

emslam::eval::ReferenceSurface loadPly(const std::string& file)
{
    std::ifstream in(file, std::ios::binary);
    if (!in)
    {
        throw std::runtime_error("cannot open '" + file + "'");
    }
    try
    {
        const PlyHeader h = readHeader(in);
        return readVertices(in, h);
    }
    catch (const std::exception& e)
    {
        throw std::runtime_error("'" + file + "': " + e.what());
    }
}

}  // namespace emslam::apps
