#include "visibility/pvs/PvsFile.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>

#include <nlohmann/json.hpp>

#include "base/Error.h"
#include "visibility/ExactSegment.h"
#include "base/JsonDepth.h"
#include "visibility/pvs/Sha256.h"
#include "visibility/pvs/ViewCells.h"

namespace sightline::pvs {

namespace {

constexpr char kPvsMagic[8] = {'S', 'L', 'P', 'V', 'S', 0, 0, 0};
constexpr char kPartMagic[8] = {'S', 'L', 'P', 'V', 'S', 'P', 'R', 'T'};
constexpr std::size_t kHashChars = 64;
/// An object's entry without instances or name: instance, count, box, name length.
constexpr std::size_t kFewestObjectBytes = 4 + 4 + 24 + 4;

void put32(std::string& out, std::uint32_t v)
{
    for (int k = 0; k < 4; ++k)
        out += char((v >> (8 * k)) & 0xff);
}
void put64(std::string& out, std::uint64_t v)
{
    for (int k = 0; k < 8; ++k)
        out += char((v >> (8 * k)) & 0xff);
}
void putFloat(std::string& out, float f)
{
    std::uint32_t bits;
    std::memcpy(&bits, &f, 4);
    put32(out, bits);
}
void putHash(std::string& out, const std::string& hex)
{
    std::string h = hex.substr(0, kHashChars);
    h.resize(kHashChars, '\0');
    out += h;
}

/// Bounds-checked little-endian reader: every read names the file on failure.
struct Reader {
    std::string_view bytes;
    std::string what;
    std::size_t at = 0;

    void need(std::size_t n, const char* field) const
    {
        if (n > bytes.size() || at > bytes.size() - n)
            throw Error(what + ": truncated (" + field + " at byte " + std::to_string(at) + " of " +
                        std::to_string(bytes.size()) + ")");
    }
    std::uint32_t u32(const char* field)
    {
        need(4, field);
        std::uint32_t v = 0;
        for (int k = 0; k < 4; ++k)
            v |= std::uint32_t(std::uint8_t(bytes[at + std::size_t(k)])) << (8 * k);
        at += 4;
        return v;
    }
    std::uint64_t u64(const char* field)
    {
        need(8, field);
        std::uint64_t v = 0;
        for (int k = 0; k < 8; ++k)
            v |= std::uint64_t(std::uint8_t(bytes[at + std::size_t(k)])) << (8 * k);
        at += 8;
        return v;
    }
    float f32(const char* field)
    {
        const std::uint32_t bits = u32(field);
        float f;
        std::memcpy(&f, &bits, 4);
        return f;
    }
    std::string_view take(std::size_t n, const char* field)
    {
        need(n, field);
        const std::string_view s = bytes.substr(at, n);
        at += n;
        return s;
    }
    std::string hash(const char* field)
    {
        std::string s(take(kHashChars, field));
        s.resize(std::strlen(s.c_str()));
        return s;
    }
};

void putBounds(std::string& out, const Bounds& b)
{
    for (int k = 0; k < 3; ++k)
        putFloat(out, b.min[k]);
    for (int k = 0; k < 3; ++k)
        putFloat(out, b.max[k]);
}
Bounds readBounds(Reader& r, const char* field)
{
    Bounds b;
    for (int k = 0; k < 3; ++k)
        b.min[k] = r.f32(field);
    for (int k = 0; k < 3; ++k)
        b.max[k] = r.f32(field);
    return b;
}

std::string number(float f)
{
    if (!std::isfinite(f))
        return "null";   // an empty object's box
    char buffer[32];
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, f);
    return std::string(buffer, result.ptr);
}
std::string vec3(const glm::vec3& v)
{
    return "[" + number(v.x) + ", " + number(v.y) + ", " + number(v.z) + "]";
}

} // namespace

std::vector<std::uint8_t> compressZeroRuns(const std::uint8_t* row, std::size_t rowBytes)
{
    std::vector<std::uint8_t> out;
    for (std::size_t k = 0; k < rowBytes;) {
        if (row[k] != 0) {
            out.push_back(row[k++]);
            continue;
        }
        std::size_t run = 0;
        while (k < rowBytes && row[k] == 0 && run < 255) {
            ++run;
            ++k;
        }
        out.push_back(0);
        out.push_back(std::uint8_t(run));
    }
    return out;
}

std::vector<std::uint8_t> decompressZeroRuns(std::string_view data, std::size_t offset, std::size_t rowBytes, std::size_t* end)
{
    std::vector<std::uint8_t> row;
    row.reserve(rowBytes);
    std::size_t k = offset;
    while (row.size() < rowBytes) {
        if (k >= data.size())
            throw Error("zero-run-length row: data ends after " + std::to_string(row.size()) + " of " +
                        std::to_string(rowBytes) + " bytes");
        const std::uint8_t b = std::uint8_t(data[k++]);
        if (b != 0) {
            row.push_back(b);
            continue;
        }
        if (k >= data.size())
            throw Error("zero-run-length row: a zero byte without its count");
        const std::size_t run = std::uint8_t(data[k++]);
        if (run == 0 || row.size() + run > rowBytes)
            throw Error("zero-run-length row: a run of " + std::to_string(run) + " zeros does not fit the row");
        row.insert(row.end(), run, 0);
    }
    if (end)
        *end = k;
    return row;
}

namespace {

/// u64 offsets (C + 1, from the start of the row data) then the rows, raw or zero-run-length.
void putRows(std::string& out, const VisibilityRows& rows, RowEncoding encoding)
{
    std::string rowData;
    std::vector<std::uint64_t> offsets;
    for (std::size_t c = 0; c < rows.cellCount(); ++c) {
        offsets.push_back(rowData.size());
        if (encoding == RowEncoding::Raw)
            rowData.append(reinterpret_cast<const char*>(rows.row(c)), rows.rowBytes());
        else {
            const auto packed = compressZeroRuns(rows.row(c), rows.rowBytes());
            rowData.append(packed.begin(), packed.end());
        }
    }
    offsets.push_back(rowData.size());
    for (std::uint64_t o : offsets)
        put64(out, o);
    out += rowData;
}

/// Fewest encoded bytes a row of `rowBytes` bytes can take: raw rows are stored whole; a
/// zero-run pair (2 bytes) stands for at most 255 bytes and a literal byte for one, so a byte of
/// encoding never stands for more than 255 bytes of row.
std::size_t fewestEncodedBytes(std::size_t rowBytes, std::uint32_t encoding)
{
    return encoding == 0 ? rowBytes : (rowBytes + 254) / 255;
}

/// Reads the offsets, then checks every row's span against the data and the encoding's fewest
/// bytes before the table is allocated: a file's declared counts never drive memory beyond what
/// its size (255 bytes of rows per byte at most) and kMaxRowTableBytes allow.
VisibilityRows readRows(Reader& r, std::uint32_t cells, std::size_t columns, std::uint32_t encoding, const char* what)
{
    const std::size_t rowBytes = (columns + 7) / 8;
    r.need((std::size_t(cells) + 1) * 8, what);
    std::vector<std::uint64_t> offsets;
    offsets.reserve(std::size_t(cells) + 1);
    for (std::uint32_t c = 0; c <= cells; ++c)
        offsets.push_back(r.u64(what));
    if (offsets.front() != 0)
        throw Error(r.what + ": " + what + " do not start at 0");
    if (offsets.back() > r.bytes.size() - r.at)
        throw Error(r.what + ": truncated (" + what + " declare " + std::to_string(offsets.back()) + " bytes of rows, " +
                    std::to_string(r.bytes.size() - r.at) + " follow)");
    const std::size_t fewest = fewestEncodedBytes(rowBytes, encoding);
    for (std::uint32_t c = 0; c < cells; ++c)
        if (offsets[c] > offsets[c + 1] || offsets[c + 1] - offsets[c] < fewest ||
            (encoding == 0 && offsets[c + 1] - offsets[c] != rowBytes))
            throw Error(r.what + ": " + what + " at cell " + std::to_string(c) + " give " +
                        (offsets[c] > offsets[c + 1] ? std::string("a negative") : std::to_string(offsets[c + 1] - offsets[c])) +
                        " bytes for a row of " + std::to_string(rowBytes) + (encoding == 0 ? " raw" : " encoded") + " bytes");
    const std::string_view rowData = r.take(std::size_t(offsets.back()), what);
    VisibilityRows rows(cells, columns);
    for (std::uint32_t c = 0; c < cells; ++c) {
        const std::string_view one = rowData.substr(offsets[c], offsets[c + 1] - offsets[c]);
        if (encoding == 0) {
            std::copy(one.begin(), one.end(), rows.row(c));
            continue;
        }
        std::vector<std::uint8_t> row;
        std::size_t end = 0;
        try {
            row = decompressZeroRuns(one, 0, rowBytes, &end);
        } catch (const Error& e) {
            throw Error(r.what + ": cell " + std::to_string(c) + ": " + e.what());
        }
        if (end != one.size())
            throw Error(r.what + ": cell " + std::to_string(c) + ": the row has bytes after its end");
        std::copy(row.begin(), row.end(), rows.row(c));
    }
    return rows;
}

/// An object's box is either empty (no triangles: +inf min, -inf max, as Bounds starts) or
/// finite, ordered and within the exact contract's coordinates.
bool sameBox(const Bounds& a, const Bounds& b) { return a.min == b.min && a.max == b.max; }

bool sameCells(const std::vector<Bounds>& a, const std::vector<Bounds>& b)
{
    return std::equal(a.begin(), a.end(), b.begin(), b.end(), sameBox);
}

bool sameObjects(const std::vector<PvsObject>& a, const std::vector<PvsObject>& b)
{
    return std::equal(a.begin(), a.end(), b.begin(), b.end(), [](const PvsObject& x, const PvsObject& y) {
        return x.name == y.name && x.instance == y.instance && x.instances == y.instances && sameBox(x.bounds, y.bounds);
    });
}

void checkObjectBounds(const Bounds& b, const std::string& what)
{
    const Bounds empty;
    if (b.min == empty.min && b.max == empty.max)
        return;
    for (int k = 0; k < 3; ++k)
        if (!std::isfinite(b.min[k]) || !std::isfinite(b.max[k]) || b.min[k] > b.max[k] ||
            std::abs(b.min[k]) > kMaxCoordinateMetres || std::abs(b.max[k]) > kMaxCoordinateMetres)
            throw Error(what + ": a box that is not finite, inverted or beyond 1e6 m");
}

} // namespace

std::string encodePvs(const PvsData& data, RowEncoding encoding)
{
    const VisibilityRows& rows = data.rows;
    if (rows.cellCount() != data.cells.size() || rows.objectCount() != data.objects.size())
        throw Error("pvs: rows do not match the cell and object tables");
    if (data.hasCellRows() && (data.cellRows.cellCount() != data.cells.size() || data.cellRows.objectCount() != data.cells.size()))
        throw Error("pvs: cell-to-cell rows do not match the cell table");
    std::string out(kPvsMagic, 8);
    put32(out, kPvsFileVersion);
    put32(out, std::uint32_t(encoding));
    put32(out, std::uint32_t(data.cells.size()));
    put32(out, std::uint32_t(data.objects.size()));
    put32(out, std::uint32_t(rows.rowBytes()));
    put32(out, data.hasCellRows() ? 1u : 0u);   // flags: bit 0, cell-to-cell rows follow the object rows
    putHash(out, data.sceneSha256);
    putHash(out, data.settingsSha256);
    for (const Bounds& b : data.cells)
        putBounds(out, b);
    for (const PvsObject& o : data.objects) {
        put32(out, o.instance);
        put32(out, std::uint32_t(o.instances.size()));
        for (std::uint32_t i : o.instances)
            put32(out, i);
        putBounds(out, o.bounds);
        put32(out, std::uint32_t(o.name.size()));
        out += o.name;
    }
    putRows(out, rows, encoding);
    if (data.hasCellRows())
        putRows(out, data.cellRows, encoding);
    return out;
}

PvsData decodePvs(std::string_view bytes, const std::string& what)
{
    Reader r{bytes, what};
    if (r.take(8, "magic") != std::string_view(kPvsMagic, 8))
        throw Error(what + ": not a Sightline .pvs file (bad magic)");
    const std::uint32_t version = r.u32("version");
    if (version != 1 && version != kPvsFileVersion)
        throw Error(what + ": .pvs version " + std::to_string(version) + ", this build reads versions 1 and " +
                    std::to_string(kPvsFileVersion));
    const std::uint32_t encoding = r.u32("encoding");
    if (encoding > 1)
        throw Error(what + ": unknown row encoding " + std::to_string(encoding));
    const std::uint32_t cells = r.u32("cell count"), objects = r.u32("object count"), rowBytes = r.u32("row bytes");
    const std::uint32_t flags = r.u32("flags");
    if (flags > (version >= 2 ? 1u : 0u))
        throw Error(what + ": unknown flags " + std::to_string(flags));
    if (rowBytes != (std::uint64_t(objects) + 7) / 8)
        throw Error(what + ": row size " + std::to_string(rowBytes) + " does not fit " + std::to_string(objects) + " objects");
    PvsData data;
    data.sceneSha256 = r.hash("scene hash");
    data.settingsSha256 = r.hash("settings hash");
    r.need(std::size_t(cells) * 24, "cell table");
    for (std::uint32_t c = 0; c < cells; ++c)
        data.cells.push_back(readBounds(r, "cell table"));
    validateCells(data.cells, what + ": cell");
    r.need(std::size_t(objects) * kFewestObjectBytes, "object table");
    for (std::uint32_t o = 0; o < objects; ++o) {
        const std::string key = what + ": object " + std::to_string(o);
        PvsObject object;
        object.instance = r.u32("object instance");
        const std::uint32_t n = r.u32("object instance count");
        r.need(std::size_t(n) * 4, "object instances");
        for (std::uint32_t k = 0; k < n; ++k)
            object.instances.push_back(r.u32("object instances"));
        if (n > 0 && (object.instances.front() != object.instance ||
                      std::adjacent_find(object.instances.begin(), object.instances.end(), std::greater_equal<>()) !=
                          object.instances.end()))
            throw Error(key + ": its instance list is not sorted from its first instance");
        object.bounds = readBounds(r, "object bounds");
        checkObjectBounds(object.bounds, key);
        const std::uint32_t length = r.u32("object name length");
        object.name = std::string(r.take(length, "object name"));
        data.objects.push_back(std::move(object));
    }
    data.rows = readRows(r, cells, objects, encoding, "row offsets");
    if (flags & 1u)
        data.cellRows = readRows(r, cells, cells, encoding, "cell row offsets");
    if (r.at != bytes.size())
        throw Error(what + ": " + std::to_string(bytes.size() - r.at) + " bytes after the rows");
    return data;
}

namespace {

/// The JSON reader's checks, each naming the key: "x.pvs.json: 'cells[3].min' must be three numbers".
struct JsonReader {
    const std::string& what;
    [[noreturn]] void fail(const std::string& key, const std::string& why) const { throw Error(what + ": '" + key + "' " + why); }
    const nlohmann::json& at(const nlohmann::json& object, const char* key, const std::string& where) const
    {
        const auto it = object.find(key);
        if (it == object.end())
            fail(where.empty() ? key : where + "." + key, "is missing");
        return *it;
    }
    /// Three numbers, or (`empty` allowed) three nulls for an empty box's corner.
    glm::vec3 corner(const nlohmann::json& value, const std::string& key, bool& isNull) const
    {
        if (!value.is_array() || value.size() != 3)
            fail(key, "must be three numbers");
        isNull = value[0].is_null() && value[1].is_null() && value[2].is_null();
        if (isNull)
            return glm::vec3(0.0f);
        glm::vec3 v(0.0f);
        for (int k = 0; k < 3; ++k) {
            if (!value[std::size_t(k)].is_number())
                fail(key, "must be three numbers");
            v[k] = value[std::size_t(k)].get<float>();
        }
        return v;
    }
    Bounds box(const nlohmann::json& object, const std::string& key, bool emptyAllowed) const
    {
        if (!object.is_object())
            fail(key, "must be an object with \"min\" and \"max\"");
        bool minNull = false, maxNull = false;
        Bounds b;
        const glm::vec3 lo = corner(at(object, "min", key), key + ".min", minNull);
        const glm::vec3 hi = corner(at(object, "max", key), key + ".max", maxNull);
        if (minNull || maxNull) {
            if (!(minNull && maxNull && emptyAllowed))
                fail(key, "must have a finite min and max");
            return b;   // empty: no triangles
        }
        b.min = lo;
        b.max = hi;
        return b;
    }
    std::uint32_t index(const nlohmann::json& value, const std::string& key) const
    {
        if (!value.is_number_unsigned() || value.get<std::uint64_t>() > std::numeric_limits<std::uint32_t>::max())
            fail(key, "must be a whole number from 0 to 4294967295");
        return value.get<std::uint32_t>();
    }
    /// `lists[c]`: sorted distinct indices below `count`, one list per row of `rows`.
    void rows(const nlohmann::json& lists, const std::string& key, std::size_t count, VisibilityRows& rows) const
    {
        if (!lists.is_array() || lists.size() != rows.cellCount())
            fail(key, "must hold one list per cell (" + std::to_string(rows.cellCount()) + ")");
        for (std::size_t c = 0; c < lists.size(); ++c) {
            const std::string row = key + "[" + std::to_string(c) + "]";
            if (!lists[c].is_array())
                fail(row, "must be a list of indices");
            std::int64_t previous = -1;
            for (std::size_t k = 0; k < lists[c].size(); ++k) {
                const std::uint32_t o = index(lists[c][k], row + "[" + std::to_string(k) + "]");
                if (o >= count || std::int64_t(o) <= previous)
                    fail(row, "must list indices below " + std::to_string(count) + ", sorted, each once");
                previous = o;
                rows.set(c, o, true);
            }
        }
    }
};

} // namespace

PvsData decodePvsJson(std::string_view text, const std::string& what)
{
    checkJsonDepth(text, what);
    nlohmann::json doc;
    try {
        doc = nlohmann::json::parse(text);
    } catch (const nlohmann::json::exception& e) {
        throw Error(what + ": not a .pvs.json (invalid JSON: " + std::string(e.what()).substr(0, 200) + ")");
    }
    const JsonReader read{what};
    if (!doc.is_object())
        throw Error(what + ": a .pvs.json must be a JSON object");
    const nlohmann::json& version = read.at(doc, "version", "");
    if (!version.is_number_integer() || version.get<std::int64_t>() != 1)
        read.fail("version", "must be 1");
    PvsData data;
    const nlohmann::json& sha = read.at(doc, "scene_sha256", "");
    if (!sha.is_string())
        read.fail("scene_sha256", "must be a string");
    data.sceneSha256 = sha.get<std::string>();
    if (const auto it = doc.find("settings_sha256"); it != doc.end()) {
        if (!it->is_string())
            read.fail("settings_sha256", "must be a string");
        data.settingsSha256 = it->get<std::string>();
    }
    const nlohmann::json& cells = read.at(doc, "cells", "");
    const nlohmann::json& objects = read.at(doc, "objects", "");
    if (!cells.is_array())
        read.fail("cells", "must be an array of boxes");
    if (!objects.is_array())
        read.fail("objects", "must be an array of objects");
    for (std::size_t c = 0; c < cells.size(); ++c)
        data.cells.push_back(read.box(cells[c], "cells[" + std::to_string(c) + "]", false));
    validateCells(data.cells, what);
    for (std::size_t o = 0; o < objects.size(); ++o) {
        const std::string key = "objects[" + std::to_string(o) + "]";
        const nlohmann::json& object = objects[o];
        PvsObject out;
        if (!object.is_object())
            read.fail(key, "must be an object");
        const nlohmann::json& name = read.at(object, "name", key);
        if (!name.is_string())
            read.fail(key + ".name", "must be a string");
        out.name = name.get<std::string>();
        out.instance = read.index(read.at(object, "instance", key), key + ".instance");
        out.instances = {out.instance};
        if (const auto it = object.find("instances"); it != object.end()) {
            if (!it->is_array() || it->empty())
                read.fail(key + ".instances", "must be a list of instance indices");
            out.instances.clear();
            for (std::size_t k = 0; k < it->size(); ++k)
                out.instances.push_back(read.index((*it)[k], key + ".instances[" + std::to_string(k) + "]"));
        }
        out.bounds = read.box(object, key, true);
        checkObjectBounds(out.bounds, what + ": " + key);
        data.objects.push_back(std::move(out));
    }
    if (data.cells.size() * ((data.objects.size() + 7) / 8) > kMaxRowTableBytes)
        throw Error(what + ": " + std::to_string(data.cells.size()) + " cells x " + std::to_string(data.objects.size()) +
                    " objects is past the largest table read");
    data.rows = VisibilityRows(data.cells.size(), data.objects.size());
    read.rows(read.at(doc, "visible", ""), "visible", data.objects.size(), data.rows);
    if (const auto it = doc.find("visible_cells"); it != doc.end()) {
        data.cellRows = VisibilityRows(data.cells.size(), data.cells.size());
        read.rows(*it, "visible_cells", data.cells.size(), data.cellRows);
    }
    return data;
}

std::string pvsJson(const PvsData& data)
{
    std::string out = "{\"version\": 1,\n \"scene_sha256\": \"" + data.sceneSha256 + "\",\n \"settings_sha256\": \"" +
                      data.settingsSha256 + "\",\n \"cells\": [";
    for (std::size_t c = 0; c < data.cells.size(); ++c)
        out += std::string(c ? ",\n  " : "\n  ") + "{\"min\": " + vec3(data.cells[c].min) + ", \"max\": " + vec3(data.cells[c].max) + "}";
    out += "],\n \"objects\": [";
    for (std::size_t o = 0; o < data.objects.size(); ++o) {
        const PvsObject& object = data.objects[o];
        out += std::string(o ? ",\n  " : "\n  ") + "{\"name\": " + nlohmann::json(object.name).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) +
               ", \"instance\": " + std::to_string(object.instance);
        if (object.instances.size() > 1) {
            out += ", \"instances\": [";
            for (std::size_t k = 0; k < object.instances.size(); ++k)
                out += (k ? ", " : "") + std::to_string(object.instances[k]);
            out += "]";
        }
        out += ", \"min\": " + vec3(object.bounds.min) + ", \"max\": " + vec3(object.bounds.max) + "}";
    }
    out += "],\n \"visible\": [";
    for (std::size_t c = 0; c < data.rows.cellCount(); ++c) {
        out += c ? ",\n  [" : "\n  [";
        const auto list = data.rows.visibleObjects(c);
        for (std::size_t k = 0; k < list.size(); ++k)
            out += (k ? ", " : "") + std::to_string(list[k]);
        out += "]";
    }
    out += "]";
    if (data.hasCellRows()) {
        out += ",\n \"visible_cells\": [";
        for (std::size_t c = 0; c < data.cellRows.cellCount(); ++c) {
            out += c ? ",\n  [" : "\n  [";
            const auto list = data.cellRows.visibleObjects(c);
            for (std::size_t k = 0; k < list.size(); ++k)
                out += (k ? ", " : "") + std::to_string(list[k]);
            out += "]";
        }
        out += "]";
    }
    out += "}\n";
    return out;
}

EncodedSizes encodedSizes(const VisibilityRows& rows)
{
    EncodedSizes s;
    s.raw = rows.cellCount() * rows.rowBytes();
    for (std::size_t c = 0; c < rows.cellCount(); ++c)
        s.compressed += compressZeroRuns(rows.row(c), rows.rowBytes()).size();
    return s;
}

std::string quake1Vis(const VisibilityRows& rows)
{
    std::string out;
    put32(out, std::uint32_t(rows.cellCount()));
    std::string visdata;
    std::vector<std::uint32_t> offsets;
    for (std::size_t c = 0; c < rows.cellCount(); ++c) {
        offsets.push_back(std::uint32_t(visdata.size()));
        const auto packed = compressZeroRuns(rows.row(c), rows.rowBytes());
        visdata.append(packed.begin(), packed.end());
    }
    for (std::uint32_t o : offsets)
        put32(out, o);
    return out + visdata;
}

std::string quake2Vis(const VisibilityRows& rows)
{
    const std::size_t n = rows.cellCount();
    std::string out;
    put32(out, std::uint32_t(n));
    const std::size_t header = 4 + 8 * n;
    std::string visdata;
    std::vector<std::uint32_t> offsets;
    for (std::size_t c = 0; c < n; ++c) {
        offsets.push_back(std::uint32_t(header + visdata.size()));
        const auto packed = compressZeroRuns(rows.row(c), rows.rowBytes());
        visdata.append(packed.begin(), packed.end());
    }
    for (std::uint32_t o : offsets) {
        put32(out, o);   // PVS
        put32(out, o);   // PHS: no hearing set is baked; the visible set stands in
    }
    return out + visdata;
}

std::string prt1(const std::vector<Bounds>& cells, double scale)
{
    struct Portal {
        std::size_t a, b;
        Bounds shared;
        int axis;
    };
    std::vector<Portal> portals;
    for (std::size_t a = 0; a < cells.size(); ++a)
        for (std::size_t b = a + 1; b < cells.size(); ++b)
            for (int axis = 0; axis < 3; ++axis) {
                const Bounds& A = cells[a];
                const Bounds& B = cells[b];
                if (A.max[axis] != B.min[axis] && B.max[axis] != A.min[axis])
                    continue;
                Bounds s;
                bool area = true;
                for (int k = 0; k < 3; ++k) {
                    s.min[k] = std::max(A.min[k], B.min[k]);
                    s.max[k] = std::min(A.max[k], B.max[k]);
                    if (k != axis && !(s.max[k] > s.min[k]))
                        area = false;
                }
                if (area)
                    portals.push_back({a, b, s, axis});
            }
    auto point = [&](const glm::vec3& p) {
        char buffer[128];
        std::snprintf(buffer, sizeof buffer, "(%.6g %.6g %.6g)", double(p.x) * scale, -double(p.z) * scale, double(p.y) * scale);
        return std::string(buffer);
    };
    std::string out = "PRT1\n" + std::to_string(cells.size()) + "\n" + std::to_string(portals.size()) + "\n";
    for (const Portal& p : portals) {
        const int u = (p.axis + 1) % 3, v = (p.axis + 2) % 3;
        glm::vec3 corner[4];
        for (int k = 0; k < 4; ++k) {
            corner[k] = p.shared.min;
            corner[k][p.axis] = p.shared.min[p.axis];
        }
        corner[1][u] = p.shared.max[u];
        corner[2][u] = p.shared.max[u];
        corner[2][v] = p.shared.max[v];
        corner[3][v] = p.shared.max[v];
        out.append("4 ").append(std::to_string(p.a)).append(" ").append(std::to_string(p.b));
        for (const glm::vec3& c : corner)
            out.append(" ").append(point(c));
        out += "\n";
    }
    return out;
}

std::vector<std::size_t> shardCells(std::size_t cellCount, std::uint32_t shard, std::uint32_t shardCount)
{
    std::vector<std::size_t> out;
    for (std::size_t c = shard; c < cellCount; c += shardCount)
        out.push_back(c);
    return out;
}

std::string encodePart(const PvsPart& part)
{
    std::string rest;
    put32(rest, part.shard);
    put32(rest, part.shardCount);
    put32(rest, std::uint32_t(part.cellIndices.size()));
    for (std::uint32_t c : part.cellIndices)
        put32(rest, c);
    const std::string body = encodePvs(part.data);
    put64(rest, body.size());
    rest += body;
    std::string out(kPartMagic, 8);
    put32(out, kPartFileVersion);
    putHash(out, sha256Hex(rest));
    return out + rest;
}

PvsPart decodePart(std::string_view bytes, const std::string& what)
{
    Reader r{bytes, what};
    if (r.take(8, "magic") != std::string_view(kPartMagic, 8))
        throw Error(what + ": not a PVS part file (bad magic)");
    const std::uint32_t version = r.u32("version");
    if (version != kPartFileVersion)
        throw Error(what + ": part version " + std::to_string(version) + ", this build reads " +
                    std::to_string(kPartFileVersion) + "; bake the shard again");
    // Verified before anything else is read: a part is a file that travels between machines.
    const std::string declared = r.hash("part SHA-256");
    if (declared != sha256Hex(bytes.substr(r.at)))
        throw Error(what + ": damaged (its bytes do not match the SHA-256 it was written with); bake the shard again");
    PvsPart part;
    part.shard = r.u32("shard");
    part.shardCount = r.u32("shard count");
    if (part.shardCount == 0 || part.shard >= part.shardCount || part.shardCount > kMaxShards)
        throw Error(what + ": shard " + std::to_string(part.shard) + "/" + std::to_string(part.shardCount) +
                    " is not valid (0 <= I < N <= " + std::to_string(kMaxShards) + ")");
    const std::uint32_t n = r.u32("cell count");
    r.need(std::size_t(n) * 4, "cell list");
    for (std::uint32_t k = 0; k < n; ++k)
        part.cellIndices.push_back(r.u32("cell list"));
    const std::uint64_t bodySize = r.u64("body size");
    if (bodySize != bytes.size() - r.at)
        throw Error(what + ": truncated or padded (body of " + std::to_string(bytes.size() - r.at) + " bytes, header says " +
                    std::to_string(bodySize) + ")");
    part.data = decodePvs(bytes.substr(r.at), what);
    const auto expected = shardCells(part.data.cells.size(), part.shard, part.shardCount);
    if (!std::equal(expected.begin(), expected.end(), part.cellIndices.begin(), part.cellIndices.end()))
        throw Error(what + ": its cell list is not shard " + std::to_string(part.shard) + "/" + std::to_string(part.shardCount) +
                    "'s");
    return part;
}

std::string partManifest(const PvsPart& part, const std::string& partSha256, const std::string& settingsText)
{
    nlohmann::json m = {{"version", 1},
                        {"scene_sha256", part.data.sceneSha256},
                        {"settings_sha256", part.data.settingsSha256},
                        {"settings", settingsText},
                        {"shard", part.shard},
                        {"shards", part.shardCount},
                        {"cells", part.data.cells.size()},
                        {"objects", part.data.objects.size()},
                        {"cells_in_part", part.cellIndices.size()},
                        {"part_sha256", partSha256}};
    return m.dump(1) + "\n";
}

PvsData mergeParts(const std::vector<PvsPart>& parts, const std::vector<std::string>& names)
{
    if (parts.empty())
        throw Error("pvs merge: no part files");
    const PvsPart& first = parts.front();
    std::map<std::uint32_t, std::size_t> seen;   // shard -> part; the count comes from a file, so no table of it
    PvsData out = first.data;
    out.rows = VisibilityRows(first.data.cells.size(), first.data.objects.size());
    if (first.data.hasCellRows())
        out.cellRows = VisibilityRows(first.data.cells.size(), first.data.cells.size());
    for (std::size_t k = 0; k < parts.size(); ++k) {
        const PvsPart& p = parts[k];
        const std::string& name = names[k];
        if (p.data.sceneSha256 != first.data.sceneSha256)
            throw Error("pvs merge: " + name + " is of another scene (scene sha256 " + p.data.sceneSha256.substr(0, 12) +
                        "..., " + names[0] + " has " + first.data.sceneSha256.substr(0, 12) + "...)");
        if (p.data.settingsSha256 != first.data.settingsSha256)
            throw Error("pvs merge: " + name + " was baked with other settings or cells (settings sha256 " +
                        p.data.settingsSha256.substr(0, 12) + "..., " + names[0] + " has " +
                        first.data.settingsSha256.substr(0, 12) + "...)");
        if (p.shardCount != first.shardCount)
            throw Error("pvs merge: " + name + " is shard " + std::to_string(p.shard) + "/" + std::to_string(p.shardCount) +
                        ", " + names[0] + " is one of " + std::to_string(first.shardCount));
        if (!sameCells(p.data.cells, first.data.cells) || !sameObjects(p.data.objects, first.data.objects))
            throw Error("pvs merge: " + name + " has another cell or object table than " + names[0]);
        if (const auto twice = seen.find(p.shard); twice != seen.end())
            throw Error("pvs merge: shard " + std::to_string(p.shard) + " given twice (" + names[twice->second] + " and " +
                        name + ")");
        seen[p.shard] = k;
        if (p.data.hasCellRows() != first.data.hasCellRows())
            throw Error("pvs merge: " + name + (p.data.hasCellRows() ? " has" : " has no") + " cell-to-cell rows, " + names[0] +
                        (first.data.hasCellRows() ? " has" : " has none"));
        for (std::uint32_t c : p.cellIndices) {
            std::copy(p.data.rows.row(c), p.data.rows.row(c) + p.data.rows.rowBytes(), out.rows.row(c));
            if (out.hasCellRows())
                std::copy(p.data.cellRows.row(c), p.data.cellRows.row(c) + p.data.cellRows.rowBytes(), out.cellRows.row(c));
        }
    }
    if (seen.size() != first.shardCount) {
        std::uint32_t missing = 0;
        while (seen.count(missing))
            ++missing;
        throw Error("pvs merge: shard " + std::to_string(missing) + "/" + std::to_string(first.shardCount) +
                    " is missing (bake it with --shard " + std::to_string(missing) + "/" + std::to_string(first.shardCount) + ")");
    }
    return out;
}

} // namespace sightline::pvs
