// SPDX-License-Identifier: GPL-3.0-or-later
/* sems_eval: the kept predictions' NumPy .npz archives (the format: predictions.h). A zip of
 * .npy members, stored without compression and without time stamps, so the same run writes the
 * same bytes; zlib gives the members' CRC-32. */
#include "predictions.h"

#include <zlib.h>
#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <type_traits>
#include <utility>
#include <variant>

namespace sems_eval {

namespace npz {
namespace {

// Little-endian bytes of an integer or an IEEE float.
template <typename T>
void put(std::string& out, T v)
{
    static_assert(std::is_trivially_copyable_v<T>);
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T)); // x86-64 and every platform GNU Radio builds on here: little-endian
    out.append(b, sizeof(T));
}

// UTF-8 to the code points of a NumPy '<U' field (4 bytes each, little-endian).
std::u32string code_points(const std::string& s)
{
    std::u32string out;
    for (size_t i = 0; i < s.size();) {
        const unsigned char c = s[i];
        const int n = c < 0x80 ? 1 : (c >> 5) == 0x6 ? 2 : (c >> 4) == 0xE ? 3 : (c >> 3) == 0x1E ? 4 : 0;
        if (n == 0 || i + n > s.size())
            throw std::invalid_argument("kept predictions: \"" + s + "\" is not UTF-8");
        char32_t cp = n == 1 ? c : c & (0x7F >> n);
        for (int k = 1; k < n; ++k)
            cp = (cp << 6) | (static_cast<unsigned char>(s[i + k]) & 0x3F);
        out.push_back(cp);
        i += n;
    }
    return out;
}

// One .npy file: the version 1.0 header (its length a multiple of 64, as NumPy writes it)
// and the data.
std::string npy(const std::string& descr, const std::vector<size_t>& shape, const std::string& data)
{
    std::string dims;
    for (size_t i = 0; i < shape.size(); ++i)
        dims += (i ? ", " : "") + std::to_string(shape[i]);
    if (shape.size() == 1)
        dims += ",";
    std::string header = "{'descr': " + descr + ", 'fortran_order': False, 'shape': (" + dims + "), }";
    const size_t unpadded = 10 + header.size() + 1;
    header += std::string((64 - unpadded % 64) % 64, ' ') + "\n";
    if (header.size() > 65535)
        throw std::length_error("kept predictions: .npy header too long");
    std::string out("\x93NUMPY\x01\x00", 8);
    put<uint16_t>(out, static_cast<uint16_t>(header.size()));
    return out + header + data;
}

// A table of columns, written as a NumPy structured array (one record per row, fields packed).
class table
{
public:
    using column = std::variant<std::vector<std::string>, std::vector<int16_t>, std::vector<int32_t>,
                                std::vector<int64_t>, std::vector<uint64_t>, std::vector<double>>;

    void add(const std::string& name, column values) { d_columns.emplace_back(name, std::move(values)); }

    std::string to_npy() const
    {
        size_t rows = 0;
        std::string descr = "[";
        std::vector<size_t> widths;
        for (size_t c = 0; c < d_columns.size(); ++c) {
            const auto& [name, col] = d_columns[c];
            const size_t n = std::visit([](const auto& v) { return v.size(); }, col);
            if (c > 0 && n != rows)
                throw std::logic_error("kept predictions: column " + name + " has another length");
            rows = n;
            std::string type;
            if (const auto* s = std::get_if<std::vector<std::string>>(&col)) {
                size_t w = 1;
                for (const auto& v : *s)
                    w = std::max(w, code_points(v).size());
                widths.push_back(w);
                type = "<U" + std::to_string(w);
            } else {
                widths.push_back(0);
                type = std::holds_alternative<std::vector<int16_t>>(col)   ? "<i2"
                       : std::holds_alternative<std::vector<int32_t>>(col) ? "<i4"
                       : std::holds_alternative<std::vector<int64_t>>(col) ? "<i8"
                       : std::holds_alternative<std::vector<uint64_t>>(col) ? "<u8"
                                                                            : "<f8";
            }
            descr += std::string(descr.size() > 1 ? ", " : "") + "('" + name + "', '" + type + "')";
        }
        descr += "]";
        std::string data;
        for (size_t r = 0; r < rows; ++r)
            for (size_t c = 0; c < d_columns.size(); ++c)
                std::visit(
                    [&](const auto& v) {
                        using T = typename std::decay_t<decltype(v)>::value_type;
                        if constexpr (std::is_same_v<T, std::string>) {
                            auto cp = code_points(v[r]);
                            cp.resize(widths[c], U'\0');
                            for (char32_t ch : cp)
                                put<uint32_t>(data, static_cast<uint32_t>(ch));
                        } else {
                            put<T>(data, v[r]);
                        }
                    },
                    d_columns[c].second);
        return npy(descr, { rows }, data);
    }

private:
    std::vector<std::pair<std::string, column>> d_columns;
};

// A zip archive of .npy members, stored (no compression), written to a temporary file and
// renamed over `path`, so a reader never sees half a file.
void write_archive(const std::string& path, const std::vector<std::pair<std::string, std::string>>& members)
{
    std::string out, directory;
    const uint16_t dos_time = 0, dos_date = (0 << 9) | (1 << 5) | 1; // 1980-01-01 00:00: no time stamp
    for (const auto& [name, data] : members) {
        if (out.size() + data.size() > 0xFFFFFFF0u)
            throw std::length_error("kept predictions: " + path + " would exceed 4 GB");
        const uint32_t crc = static_cast<uint32_t>(::crc32(0L, reinterpret_cast<const Bytef*>(data.data()), static_cast<uInt>(data.size()))), size = static_cast<uint32_t>(data.size()),
                       offset = static_cast<uint32_t>(out.size());
        put<uint32_t>(out, 0x04034b50);
        for (uint16_t v : { uint16_t(20), uint16_t(0), uint16_t(0), dos_time, dos_date })
            put<uint16_t>(out, v); // version needed, flags, stored, time, date
        put<uint32_t>(out, crc);
        put<uint32_t>(out, size);
        put<uint32_t>(out, size);
        put<uint16_t>(out, static_cast<uint16_t>(name.size()));
        put<uint16_t>(out, 0);
        out += name;
        out += data;
        put<uint32_t>(directory, 0x02014b50);
        for (uint16_t v : { uint16_t(20), uint16_t(20), uint16_t(0), uint16_t(0), dos_time, dos_date })
            put<uint16_t>(directory, v); // made by, needed, flags, stored, time, date
        put<uint32_t>(directory, crc);
        put<uint32_t>(directory, size);
        put<uint32_t>(directory, size);
        for (uint16_t v : { static_cast<uint16_t>(name.size()), uint16_t(0), uint16_t(0), uint16_t(0), uint16_t(0) })
            put<uint16_t>(directory, v); // name, extra, comment, disk, internal attributes
        put<uint32_t>(directory, 0);     // external attributes
        put<uint32_t>(directory, offset);
        directory += name;
    }
    const uint32_t at = static_cast<uint32_t>(out.size());
    out += directory;
    put<uint32_t>(out, 0x06054b50);
    for (uint16_t v : { uint16_t(0), uint16_t(0), static_cast<uint16_t>(members.size()),
                        static_cast<uint16_t>(members.size()) })
        put<uint16_t>(out, v);
    put<uint32_t>(out, static_cast<uint32_t>(directory.size()));
    put<uint32_t>(out, at);
    put<uint16_t>(out, 0);
    const std::string tmp = path + ".tmp";
    {
        std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
        f.write(out.data(), static_cast<std::streamsize>(out.size()));
        if (!f)
            throw std::runtime_error("cannot write " + tmp);
    }
    std::filesystem::rename(tmp, path);
}

const char* format_name = "sems_eval kept predictions";
constexpr int32_t format_version = 1;

} // namespace
} // namespace npz

void kept_predictions::write() const
{
    npz::table info;
    info.add("format", std::vector<std::string>{ npz::format_name });
    info.add("version", std::vector<int32_t>{ npz::format_version });
    info.add("experiment", std::vector<std::string>{ d_experiment });
    info.add("quantity", std::vector<std::string>{ d_kind == kind::class_id ? "class_id" : "delay_index_error" });
    info.add("bits", std::vector<int32_t>{ d_kind == kind::class_id ? bits() : 0 });
    info.add("n_frames", std::vector<int32_t>{ static_cast<int32_t>(d_frames) });
    npz::table series;
    std::vector<std::string> scenario, method, mask;
    std::vector<int32_t> n_pilots;
    std::vector<double> snr;
    std::vector<int64_t> train_seed;
    std::vector<uint64_t> test_seed;
    for (const auto& k : d_keys) {
        scenario.push_back(k.scenario);
        method.push_back(k.method);
        mask.push_back(k.mask);
        n_pilots.push_back(k.n_pilots);
        snr.push_back(k.snr_db);
        train_seed.push_back(k.train_seed ? static_cast<int64_t>(*k.train_seed) : -1);
        test_seed.push_back(k.test_seed);
    }
    series.add("scenario", scenario);
    series.add("method", method);
    series.add("mask", mask);
    series.add("n_pilots", n_pilots);
    series.add("snr_db", snr);
    series.add("train_seed", train_seed);
    series.add("test_seed", test_seed);
    std::string values;
    std::string descr;
    size_t width = 0;
    if (d_kind == kind::class_id) {
        const int b = bits();
        width = (d_frames * b + 7) / 8;
        descr = "'|u1'";
        for (const auto& row : d_ids) {
            std::string packed(width, '\0');
            size_t bit = 0;
            for (int16_t id : row) {
                const unsigned v = static_cast<unsigned>(id + 1);
                for (int k = b - 1; k >= 0; --k, ++bit)
                    if ((v >> k) & 1u)
                        packed[bit / 8] = static_cast<char>(packed[bit / 8] | (0x80 >> (bit % 8)));
            }
            values += packed;
        }
    } else {
        width = d_frames;
        descr = "'<f4'";
        for (const auto& row : d_errors)
            for (float e : row)
                npz::put<float>(values, e);
    }
    npz::write_archive(d_path, { { "info.npy", info.to_npy() },
                                 { "series.npy", series.to_npy() },
                                 { "values.npy", npz::npy(descr, { d_keys.size(), width }, values) } });
}

void truth_file::write() const
{
    npz::table info, scenarios;
    info.add("format", std::vector<std::string>{ npz::format_name });
    info.add("version", std::vector<int32_t>{ npz::format_version });
    info.add("experiment", std::vector<std::string>{ d_experiment });
    info.add("quantity", std::vector<std::string>{ "truth" });
    std::vector<std::string> names;
    std::vector<uint64_t> seeds;
    std::vector<int32_t> counts;
    std::vector<std::pair<std::string, std::string>> members{ { "info.npy", info.to_npy() } };
    for (const auto& s : d_scenarios) {
        names.push_back(s.name);
        seeds.push_back(s.test_seed);
        counts.push_back(static_cast<int32_t>(s.truth.size()));
        std::vector<int64_t> frame;
        std::vector<int16_t> class_id;
        std::vector<double> delay, range, velocity;
        for (const auto& t : s.truth) {
            frame.push_back(static_cast<int64_t>(t.frame));
            class_id.push_back(static_cast<int16_t>(t.class_id));
            delay.push_back(t.delay_index);
            range.push_back(t.range_m);
            velocity.push_back(t.velocity_mps);
        }
        npz::table frames, classes;
        frames.add("frame", frame);
        frames.add("class_id", class_id);
        frames.add("delay_index", delay);
        frames.add("range_m", range);
        frames.add("velocity_mps", velocity);
        std::vector<int32_t> ids;
        for (size_t k = 0; k < s.classes.size(); ++k)
            ids.push_back(static_cast<int32_t>(k));
        classes.add("class_id", ids);
        classes.add("name", s.classes);
        members.push_back({ "frames_" + s.name + ".npy", frames.to_npy() });
        members.push_back({ "classes_" + s.name + ".npy", classes.to_npy() });
    }
    scenarios.add("scenario", names);
    scenarios.add("test_seed", seeds);
    scenarios.add("n_frames", counts);
    members.insert(members.begin() + 1, { "scenarios.npy", scenarios.to_npy() });
    npz::write_archive(d_path, members);
}

} // namespace sems_eval
