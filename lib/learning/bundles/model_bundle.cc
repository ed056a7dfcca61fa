// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: model bundle directory (bundle.json + the mask and weights files it names; weights via bundle_decoder). */
#include "core/common/json_object.h"
#include "core/common/named_files.h"
#include <gnuradio/sems/core/common/limits.h>
#include <gnuradio/sems/learning/networks/network_settings.h>
#include <gnuradio/sems/learning/bundles/model_bundle.h>
#include <filesystem>
#include <algorithm>
#include <climits>
#include <cstdlib>
#include <sys/stat.h>
#include <stdexcept>
#include <unistd.h>

namespace gr {
namespace sems {

namespace {
using detail::library_folder;
using detail::real_path;

std::string join(const std::string& dir, const std::string& file)
{
    if (dir.empty())
        return file;
    return dir.back() == '/' ? dir + file : dir + "/" + file;
}

bool is_directory(const std::string& path)
{
    struct stat st;
    return ::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

bool is_file(const std::string& path)
{
    struct stat st;
    return ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

bool under(const std::string& path, const std::string& folder)
{
    return !folder.empty() && path.size() > folder.size() && path.compare(0, folder.size(), folder) == 0 &&
           path[folder.size()] == '/';
}

// Where CMake configured the build (lib/learning/CMakeLists.txt defines these for this file).
#ifndef SEMS_BUILD_SOURCE_DIR
#define SEMS_BUILD_SOURCE_DIR ""
#endif
#ifndef SEMS_BUILD_BINARY_DIR
#define SEMS_BUILD_BINARY_DIR ""
#endif
#ifndef SEMS_INSTALL_MODELS_DIR
#define SEMS_INSTALL_MODELS_DIR ""
#endif
#ifndef SEMS_LIBDIR_TO_MODELS
#define SEMS_LIBDIR_TO_MODELS ""
#endif

// A file of the bundle as bundle.json names it: a plain file name inside the bundle
// directory (no folders, not "." or ".."), `fallback` when the key is absent.
std::string bundle_file_name(const nlohmann::json& j, const char* key, const char* fallback, const std::string& path)
{
    if (!j.contains(key))
        return fallback;
    const auto name = json_read::string(j[key], key, path);
    if (name.empty() || name == "." || name == ".." || name.find('/') != std::string::npos)
        json_read::fail(path, key, "must be a file name inside the bundle directory, got \"" + name + "\"");
    return name;
}

// The decoder kinds each task accepts.
std::vector<std::string> decoder_kinds_for(task_kind t)
{
    if (t == task_kind::classify)
        return { "classifier_spectral", "classifier_resnet" };
    return { "delay_correlation" };
}
} // namespace

std::string task_name(task_kind t) { return t == task_kind::classify ? "classify" : "delay"; }

task_kind task_from_name(const std::string& name)
{
    if (name == "classify")
        return task_kind::classify;
    if (name == "delay")
        return task_kind::delay;
    throw std::invalid_argument("unknown task \"" + name + "\" (known: classify, delay)");
}

nlohmann::json model_bundle::to_json() const
{
    nlohmann::json j = { { "format", format_name },
                         { "version", format_version },
                         { "task", task_name(task) },
                         { "class_names", class_names },
                         { "decoder", decoder },
                         { "frame", frame.to_json() },
                         { "n_pilots", mask.size() },
                         { "mask_file", mask_name },
                         { "weights_file", weights_name },
                         { "training", training.is_null() ? nlohmann::json::object() : training },
                         { "metrics", metrics.is_null() ? nlohmann::json::object() : metrics } };
    if (task == task_kind::classify && library)
        j["class_library"] = library->to_json();
    if (!track.is_null())
        j["track"] = track;
    if (!position.is_null())
        j["position"] = position;
    return j;
}

void model_bundle::save(const std::string& dir) const
{
    std::error_code ec; // parent folders too, like mkdir -p
    std::filesystem::create_directories(dir, ec);
    if (!is_directory(dir))
        throw std::invalid_argument(dir + ": cannot create the bundle directory" + (ec ? " (" + ec.message() + ")" : ""));
    if (super_frame)
        super_frame->save(join(dir, mask_name)); // F sets; `mask` is its set 0
    else
        mask.save(join(dir, mask_name));
    json_read::write_file(join(dir, bundle_file), to_json());
}

std::string model_bundle::weights_path() const { return join(directory, weights_name); }

std::vector<std::string> model_bundle::search_path()
{
    std::vector<std::string> dirs;
    auto add = [&dirs](const std::string& d) {
        if (!d.empty() && std::find(dirs.begin(), dirs.end(), d) == dirs.end())
            dirs.push_back(d);
    };
    if (const char* env = std::getenv("SEMS_MODELS_PATH")) {
        const std::string list = env;
        size_t start = 0;
        while (start <= list.size()) {
            const auto end = std::min(list.find(':', start), list.size());
            add(list.substr(start, end - start));
            start = end + 1;
        }
    }
    if (const char* src = std::getenv("SEMS_SOURCE_DIR"); src && *src)
        add(join(src, "models"));
    const std::string libdir = library_folder();
    const std::string build_dir = SEMS_BUILD_BINARY_DIR;
    if (!build_dir.empty() && under(libdir, real_path(build_dir)))
        add(join(SEMS_BUILD_SOURCE_DIR, "models")); // running from the build tree
    else if (!libdir.empty() && *SEMS_LIBDIR_TO_MODELS)
        add(real_path(join(libdir, SEMS_LIBDIR_TO_MODELS))); // next to the installed library
    add(SEMS_INSTALL_MODELS_DIR);
    return dirs;
}

std::string model_bundle::find(const std::string& name)
{
    if (name.empty())
        throw std::invalid_argument("model bundle: no bundle name or directory given");
    if (is_directory(name)) {
        // A folder of the working directory is taken as given, before the search path. When it
        // holds no bundle while the search path has a bundle of that name, say so here: load()
        // would only report the missing bundle.json, not the bundle the user likely meant.
        if (!is_file(join(name, bundle_file)) && name.find('/') == std::string::npos) {
            for (const auto& d : search_path()) {
                const auto candidate = join(d, name);
                if (is_file(join(candidate, bundle_file)))
                    throw std::invalid_argument(
                        name + ": the folder of that name in the working directory is taken as given and holds no " +
                        bundle_file + "; the bundle \"" + name + "\" of the search path is " + candidate +
                        ": give that path, or run from another directory");
            }
        }
        return name;
    }
    std::string searched;
    if (name.front() != '/') {
        for (const auto& d : search_path()) {
            const auto candidate = join(d, name);
            if (is_file(join(candidate, bundle_file)))
                return candidate;
            searched += "\n  " + candidate;
        }
    }
    char cwd[PATH_MAX];
    const std::string here = ::getcwd(cwd, sizeof cwd) ? std::string(cwd) : std::string("?");
    throw std::invalid_argument(name + ": model bundle directory does not exist; searched:\n  " + name +
                                " (as given, working directory " + here + ")" + searched +
                                "\n(a bundle name is looked up in $SEMS_MODELS_PATH, the source tree's "
                                "models/ and the installed share/gr-sems/models)");
}

model_bundle model_bundle::load(const std::string& name)
{
    const std::string dir = find(name); // names every place searched when not found
    const std::string path = join(dir, bundle_file);
    const auto j = json_read::parse_file(path); // names the file when missing or malformed
    json_read::check_format(j, format_name, format_version, path);

    model_bundle b;
    b.directory = dir;
    json_read::object_reader r(j, path); // every key is read or refused by r.finish()
    r.allow("format");
    r.allow("version");
    const auto task = r.string("task");
    try {
        b.task = task_from_name(task);
    } catch (const std::invalid_argument& e) {
        json_read::fail(path, "task", e.what());
    }
    b.frame = frame_settings::from_json(r.require("frame"), path + ": frame");
    b.decoder = r.require("decoder");
    json_read::object_reader rd(b.decoder, path, "decoder");
    const auto kind = rd.string("kind");
    const auto kinds = decoder_kinds_for(b.task);
    if (std::find(kinds.begin(), kinds.end(), kind) == kinds.end()) {
        std::string known;
        for (const auto& k : kinds)
            known += (known.empty() ? "\"" : ", \"") + k + "\"";
        json_read::fail(path, "decoder.kind",
                        "task \"" + task + "\" needs a " + known + " decoder, got \"" + kind + "\"");
    }
    // The settings are validated here (unknown keys, ranges), before any weights are read.
    const auto* settings = rd.find("settings");
    const nlohmann::json no_settings = nlohmann::json::object();
    const std::string where = path + ": decoder.settings";
    rd.finish();
    if (b.task == task_kind::classify) {
        const auto& names = r.array("class_names", 2, limits::max_classes);
        for (size_t i = 0; i < names.size(); ++i) {
            const std::string f = "class_names[" + std::to_string(i) + "]";
            b.class_names.push_back(json_read::string(names[i], f, path));
            if (b.class_names.back().empty())
                json_read::fail(path, f, "is empty");
            if (std::count(b.class_names.begin(), b.class_names.end(), b.class_names.back()) > 1)
                json_read::fail(path, f, "\"" + b.class_names.back() + "\" is listed twice");
        }
        // The names, n_classes (given or the default) and hence the weights' shape agree:
        // the sink never reads past the probability vector or mislabels a class.
        const auto cs = nn::classifier_settings::from_json(settings ? *settings : no_settings, where);
        if (cs.n_classes != static_cast<int>(b.class_names.size()))
            json_read::fail(path, "class_names",
                            "has " + std::to_string(b.class_names.size()) + " names but the decoder has " +
                                std::to_string(cs.n_classes) + " classes (decoder.settings.n_classes" +
                                (settings && settings->contains("n_classes") ? "" : ", by default") + ")");
    } else {
        if (r.has("class_names") && !r.require("class_names").empty())
            json_read::fail(path, "class_names", "a delay model has no classes");
        nn::delay_settings::from_json(settings ? *settings : no_settings, where);
    }
    // The bundle's own files are the ones bundle.json names (the defaults for older bundles).
    r.allow("mask_file");
    r.allow("weights_file");
    b.mask_name = bundle_file_name(j, "mask_file", mask_file, path);
    b.weights_name = bundle_file_name(j, "weights_file", weights_file, path);
    const auto& mask_name = b.mask_name;
    {
        auto sf = super_frame_mask::load(join(dir, mask_name)); // names mask.json in its errors; F = 1 for a frame's mask
        b.mask = sf.set(0);
        if (sf.n_frames() > 1)
            b.super_frame = std::move(sf);
    }
    try {
        if (b.super_frame)
            b.super_frame->check_frame(b.frame, path);
        b.mask.check_frame(b.frame, path);
    } catch (const std::invalid_argument& e) {
        json_read::fail(join(dir, mask_name), "", std::string("does not match bundle.json: ") + e.what());
    }
    const auto np = r.integer("n_pilots", 1, limits::max_grid);
    if (np != b.mask.size())
        json_read::fail(join(dir, mask_name), "pilots",
                        "holds " + std::to_string(b.mask.size()) + " pilots but bundle.json says n_pilots = " +
                            std::to_string(np));
    // The class library it was trained on (older bundles: the paper's table).
    if (b.task == task_kind::classify) {
        if (r.has("class_library")) {
            b.library = class_library::from_json(r.require("class_library"), path + ": class_library");
            const auto known = b.library->class_names();
            for (const auto& name : b.class_names)
                if (std::find(known.begin(), known.end(), name) == known.end())
                    json_read::fail(path, "class_names",
                                    "\"" + name + "\" is not a class of its class_library \"" + b.library->name() + "\"");
        } else {
            b.library = class_library::paper();
        }
    } else if (r.has("class_library")) {
        json_read::fail(path, "class_library", "a delay model has no classes");
    }
    // Free-form records of how the bundle was made and what it measured.
    r.allow("training");
    r.allow("metrics");
    if (const auto* track = r.find("track")) { // checked in full by track_classifier
        if (b.task != task_kind::classify)
            json_read::fail(path, "track", "decisions over a track are a classifier's");
        if (!track->is_object())
            json_read::fail(path, "track", "expected a JSON object, got " + json_read::object_reader::short_dump(*track));
        b.track = *track;
    }
    if (const auto* position = r.find("position")) { // checked in full by position_estimator
        if (b.task != task_kind::delay)
            json_read::fail(path, "position", "a position bundle is a delay bundle with an angle decoder");
        if (!position->is_object())
            json_read::fail(path, "position", "expected a JSON object, got " + json_read::object_reader::short_dump(*position));
        b.position = *position;
    }
    r.finish();
    b.training = j.value("training", nlohmann::json::object());
    b.metrics = j.value("metrics", nlohmann::json::object());
    return b;
}

void model_bundle::check_library(const class_library& input, const std::string& who) const
{
    if (task != task_kind::classify || !library)
        return;
    const auto why = library->difference(input);
    if (!why.empty())
        throw std::runtime_error(who + ": the bundle " + (directory.empty() ? std::string("(unsaved)") : directory) +
                                 " was trained on class library \"" + library->name() +
                                 "\" but its input's frames come from class library \"" + input.name() +
                                 "\": " + why);
}

void model_bundle::check_compatible(const frame_settings& fs,
                                    int n_pilots,
                                    task_kind expected,
                                    const std::string& who) const
{
    const std::string what = who + ": model bundle " + (directory.empty() ? std::string("(in memory)") : directory);
    if (task != expected)
        throw std::invalid_argument(what + " is a \"" + task_name(task) + "\" model, this block needs \"" +
                                    task_name(expected) + "\"");
    if (n_pilots != mask.size())
        throw std::invalid_argument(what + " expects N_p = " + std::to_string(mask.size()) +
                                    " pilots per frame, the stream carries " + std::to_string(n_pilots));
    frame.require_same(fs, what, "the bundle's frame", "the stream's frame");
}

} // namespace sems
} // namespace gr
