// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: a model bundle's card (model_card.json): read and written here for sems_train,
 * sems_eval and the tests alike (apps/model_card_speed.h times the decoder for it). */
#include "core/common/json_object.h"
#include <gnuradio/sems/learning/bundles/model_card.h>
#include <algorithm>
#include <climits>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

namespace gr {
namespace sems {

namespace {
using nlohmann::json;

// Figures keep 6 significant digits: more would be noise of the test set, and a card is read.
double sig6(double x)
{
    if (x == 0.0 || !std::isfinite(x))
        return x;
    std::ostringstream s;
    s.precision(6);
    s << x;
    return std::stod(s.str());
}

std::string folder_name(const std::string& dir)
{
    std::string d = dir;
    while (d.size() > 1 && d.back() == '/')
        d.pop_back();
    const auto slash = d.rfind('/');
    return slash == std::string::npos ? d : d.substr(slash + 1);
}

// The value after `flag` in a recorded command line ("--frame X" or "--frame=X"), or "".
std::string flag_value(const std::string& command, const std::string& flag)
{
    std::istringstream in(command);
    std::string word;
    while (in >> word) {
        if (word == flag) {
            std::string value;
            in >> value;
            return value;
        }
        if (word.rfind(flag + "=", 0) == 0)
            return word.substr(flag.size() + 1);
    }
    return "";
}

json figures_json(const model_card::snr_figures& f)
{
    json j = { { "snr_db", f.snr_db }, { "frames", f.frames } };
    auto put = [&j](const char* key, const std::optional<double>& v) {
        if (v)
            j[key] = sig6(*v);
    };
    put("accuracy", f.accuracy);
    put("first_frame_accuracy", f.first_frame_accuracy);
    put("mae_index", f.mae_index);
    put("mae_m", f.mae_m);
    put("median_abs_error_index", f.median_abs_error_index);
    put("rmse_azimuth_rad", f.rmse_azimuth_rad);
    put("crb_azimuth_rad", f.crb_azimuth_rad);
    return j;
}
} // namespace

std::string model_card::default_summary(const model_bundle& b)
{
    std::ostringstream s;
    if (b.task == task_kind::classify) {
        s << "classify";
        for (size_t i = 0; i < b.class_names.size(); ++i)
            s << (i ? ", " : " ") << b.class_names[i];
        if (b.library)
            s << " (class library " << b.library->name() << ")";
    } else if (!b.position.is_null()) {
        const auto& array = b.position.value("array", nlohmann::json::object());
        s << "position (delay and azimuth) of the target of interest";
        if (array.contains("receive") && array.at("receive").contains("positions_m"))
            s << " with an array of " << array.at("receive").at("positions_m").size() << " receive elements";
    } else {
        s << "delay of the target of interest's first path";
    }
    s << " from " << b.mask.size() << " pilots" << (b.position.is_null() ? "" : " per element");
    if (!b.track.is_null())
        s << ", decided over the target's track";
    return s.str();
}

model_card model_card::of_bundle(const model_bundle& b)
{
    model_card c;
    c.bundle = folder_name(b.directory);
    c.summary = default_summary(b);
    c.task = b.task;
    c.frame = b.frame;
    // The preset the training command named (sems_train --frame, default paper), when the
    // bundle's frame is that preset unchanged.
    const std::string command = b.training.is_object() ? b.training.value("command_line", std::string()) : "";
    std::string preset = flag_value(command, "--frame");
    if (preset.empty())
        preset = "paper";
    try {
        if (frame_file::find(preset).frame == b.frame)
            c.frame_preset = preset;
    } catch (const std::invalid_argument&) {
        // a frame file that is no longer where training found it: the card keeps the frame itself
    }
    if (b.task == task_kind::classify) {
        c.classes = b.class_names;
        c.class_library = b.library ? b.library->name() : class_library::paper()->name();
    }
    c.n_pilots = b.mask.size();
    const auto& origin = b.mask.origin();
    c.mask_origin = origin.is_object() && origin.contains("kind") && origin.at("kind").is_string()
                        ? origin.at("kind").get<std::string>()
                        : "";
    const std::string mask_file = b.training.is_object() ? b.training.value("mask_file", std::string()) : "";
    const std::string pattern = b.training.is_object() ? b.training.value("mask_pattern", std::string()) : "";
    c.mask = !mask_file.empty() ? mask_file : !pattern.empty() ? "pattern " + pattern : "learned";
    c.pilot_phases = b.mask.phase_sequence();
    if (c.pilot_phases.empty() && !b.mask.zero_phases())
        c.pilot_phases = "explicit";
    if (!b.track.is_null()) {
        // `sems_train --from` retrains the frame classifier; the track's own command trains the decision.
        c.retrain_recorded = "track.training.command_line";
    } else if (!b.position.is_null()) {
        // `sems_train --from` retrains the delay decoder; the position record's command trains the angle network.
        c.retrain_recorded = "position.training.command_line";
    } else {
        c.retrain_command = "sems_train --from " + b.directory + " --out retrained/" + c.bundle;
        c.retrain_recorded = "training.command_line";
    }
    return c;
}

const model_card::snr_figures& model_card::cited() const
{
    for (const auto& f : test.by_snr)
        if (f.snr_db == cite_snr_db)
            return f;
    throw std::invalid_argument("model card of " + bundle + ": no figures at the cited SNR " +
                                std::to_string(cite_snr_db) + " dB");
}

json model_card::to_json() const
{
    json j = { { "format", format_name },
               { "version", format_version },
               { "bundle", bundle },
               { "summary", summary },
               { "cite_snr_db", cite_snr_db },
               { "task", task_name(task) } };
    j["frame"] = frame_preset.empty() ? frame.to_json() : json(frame_preset);
    if (task == task_kind::classify) {
        j["class_library"] = class_library;
        j["classes"] = classes;
    }
    j["pilots"] = { { "n_pilots", n_pilots }, { "mask", mask }, { "mask_origin", mask_origin } };
    if (!pilot_phases.empty())
        j["pilots"]["phases"] = pilot_phases;
    json t = { { "measured_by", test.measured_by }, { "command", test.command }, { "frames", test.frames },
               { "scene", test.scene },             { "seed", test.seed } };
    if (!test.radio.empty())
        t["radio"] = test.radio;
    if (test.track_frames > 0)
        t["track_frames"] = test.track_frames;
    t["by_snr"] = json::array();
    for (const auto& f : test.by_snr)
        t["by_snr"].push_back(figures_json(f));
    j["test"] = t;
    j["speed"] = { { "threads", speed.threads },         { "batch", speed.batch },   { "snr_db", speed.snr_db },
                   { "frames", speed.frames },           { "repeats", speed.repeats },
                   { "decoder_fps", speed.decoder_fps }, { "anchor", speed.anchor }, { "anchor_fps", speed.anchor_fps } };
    j["retrain"] = { { "recorded", retrain_recorded } };
    if (!retrain_command.empty())
        j["retrain"]["command"] = retrain_command;
    return j;
}

model_card model_card::from_json(const json& j, const std::string& source)
{
    using json_read::fail;
    auto top = json_read::file_object(j, format_name, format_version, source);
    model_card c;
    c.bundle = top.string("bundle");
    if (c.bundle.empty())
        fail(source, "bundle", "is empty");
    c.summary = top.string("summary");
    c.cite_snr_db = top.number("cite_snr_db");
    const auto task = top.string("task");
    try {
        c.task = task_from_name(task);
    } catch (const std::invalid_argument& e) {
        fail(source, "task", e.what());
    }
    const auto& frame = top.require("frame");
    if (frame.is_string()) {
        c.frame_preset = frame.get<std::string>();
        if (c.frame_preset.empty())
            fail(source, "frame", "an empty preset name (give a preset's name or the frame's settings)");
        try {
            c.frame = frame_file::find(c.frame_preset).frame;
        } catch (const std::invalid_argument& e) {
            fail(source, "frame", e.what());
        }
    } else {
        c.frame = frame_settings::from_json(frame, source + ": frame");
    }
    if (c.task == task_kind::classify) {
        c.class_library = top.string("class_library");
        const auto& names = top.array("classes", 2, 1000);
        for (size_t i = 0; i < names.size(); ++i)
            c.classes.push_back(json_read::string(names[i], "classes[" + std::to_string(i) + "]", source));
    } else if (top.has("classes") || top.has("class_library")) {
        fail(source, top.has("classes") ? "classes" : "class_library", "a delay model has no classes");
    }
    {
        auto p = top.object("pilots");
        c.n_pilots = p.int_required("n_pilots", 1, INT_MAX);
        c.mask = p.string("mask");
        c.mask_origin = p.string("mask_origin");
        c.pilot_phases = p.string_or("phases", "");
        p.finish();
    }
    {
        auto t = top.object("test");
        c.test.measured_by = t.string("measured_by");
        c.test.command = t.string("command");
        if (c.test.command.empty())
            fail(source, "test.command", "is empty (the command that measured the figures)");
        c.test.frames = t.string("frames");
        c.test.scene = t.string("scene");
        c.test.seed = static_cast<uint64_t>(t.integer("seed", 0, LLONG_MAX));
        c.test.radio = t.string_or("radio", "");
        c.test.track_frames = t.int_or("track_frames", 0, 1, INT_MAX);
        const auto& rows = t.array("by_snr", 1, 1000);
        std::set<double> seen;
        for (size_t i = 0; i < rows.size(); ++i) {
            json_read::object_reader r(rows[i], source, "test.by_snr[" + std::to_string(i) + "]");
            snr_figures f;
            f.snr_db = r.number("snr_db");
            if (!seen.insert(f.snr_db).second)
                fail(source, r.field("snr_db"), "SNR " + std::to_string(f.snr_db) + " dB is listed twice");
            f.frames = r.int_required("frames", 1, INT_MAX);
            // A figure the task has (required or optional), or one it must not have.
            enum class need { required, optional, refused };
            auto in = [&](const char* key, double lo, double hi, need n) -> std::optional<double> {
                if (n == need::refused) {
                    if (r.has(key))
                        fail(source, r.field(key),
                             std::string("does not belong to a ") + (c.task == task_kind::classify ? "classifier" : "delay model") +
                                 (c.test.track_frames > 0 ? "'s track figures" : "'s figures"));
                    return std::nullopt;
                }
                if (n == need::optional && !r.has(key))
                    return std::nullopt;
                return r.number_in(key, 0.0, lo, hi, true);
            };
            const bool cls = c.task == task_kind::classify, track = c.test.track_frames > 0;
            const auto classify_only = cls ? need::required : need::refused, delay_only = cls ? need::refused : need::required;
            f.accuracy = in("accuracy", 0.0, 1.0, classify_only);
            f.first_frame_accuracy = in("first_frame_accuracy", 0.0, 1.0, cls && track ? need::optional : need::refused);
            f.mae_index = in("mae_index", 0.0, HUGE_VAL, delay_only);
            f.mae_m = in("mae_m", 0.0, HUGE_VAL, delay_only);
            f.median_abs_error_index = in("median_abs_error_index", 0.0, HUGE_VAL, delay_only);
            f.rmse_azimuth_rad = in("rmse_azimuth_rad", 0.0, HUGE_VAL, cls ? need::refused : need::optional);
            f.crb_azimuth_rad = in("crb_azimuth_rad", 0.0, HUGE_VAL, cls ? need::refused : need::optional);
            r.finish();
            c.test.by_snr.push_back(f);
        }
        t.finish();
    }
    if (std::none_of(c.test.by_snr.begin(), c.test.by_snr.end(),
                     [&c](const snr_figures& f) { return f.snr_db == c.cite_snr_db; }))
        fail(source, "cite_snr_db", "no test.by_snr entry at " + std::to_string(c.cite_snr_db) +
                                        " dB (the figure to cite is one of the measured ones)");
    {
        auto s = top.object("speed");
        c.speed.threads = s.int_required("threads", 1, 1024);
        c.speed.batch = s.int_required("batch", 1, INT_MAX);
        c.speed.snr_db = s.number("snr_db");
        c.speed.frames = s.int_required("frames", 1, INT_MAX);
        c.speed.repeats = s.int_required("repeats", 1, INT_MAX);
        c.speed.decoder_fps = s.number_in("decoder_fps", 0.0, 1e-9, HUGE_VAL, true);
        c.speed.anchor = s.string("anchor");
        c.speed.anchor_fps = s.number_in("anchor_fps", 0.0, 1e-9, HUGE_VAL, true);
        s.finish();
    }
    {
        auto r = top.object("retrain");
        c.retrain_recorded = r.string("recorded");
        c.retrain_command = r.string_or("command", "");
        if (c.retrain_recorded.empty())
            fail(source, "retrain.recorded", "is empty (the key of bundle.json that records the training command)");
        r.finish();
    }
    top.finish();
    return c;
}

model_card model_card::load(const std::string& path)
{
    const std::string file =
        std::filesystem::is_directory(path) ? (path.back() == '/' ? path : path + "/") + card_file : path;
    return from_json(json_read::parse_file(file), file);
}

void model_card::save(const std::string& dir) const
{
    // The top-level keys in reading order (what, then how it was measured), not alphabetical.
    const json j = to_json();
    nlohmann::ordered_json o;
    for (const char* key : { "format", "version", "bundle", "summary", "task", "frame", "class_library", "classes",
                             "pilots", "cite_snr_db", "test", "speed", "retrain" })
        if (j.contains(key))
            o[key] = j.at(key);
    const std::string path = (dir.back() == '/' ? dir : dir + "/") + card_file;
    std::ofstream out(path);
    if (!out)
        json_read::fail(path, "", "cannot open file for writing");
    out << o.dump(2) << "\n";
    if (!out)
        json_read::fail(path, "", "write failed");
}

} // namespace sems
} // namespace gr
