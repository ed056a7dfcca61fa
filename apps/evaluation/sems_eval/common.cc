// SPDX-License-Identifier: GPL-3.0-or-later
/* sems_eval: test frames, scenes, metrics, CSV output and the decoder cache. */
#include "eval.h"
#include <gnuradio/sems/learning/bundles/bundle_decoder.h>
#include <gnuradio/sems/core/scene/target_class.h>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <iomanip>
#include <random>
#include <sstream>
#include <stdexcept>

namespace fsys = std::filesystem;

namespace sems_eval {

std::string now_utc()
{
    const std::time_t t = std::time(nullptr);
    char buf[32];
    std::strftime(buf, sizeof buf, "%H:%M:%S", std::gmtime(&t));
    return buf;
}

double seconds_between(std::chrono::steady_clock::time_point a, std::chrono::steady_clock::time_point b)
{
    return std::chrono::duration<double>(b - a).count();
}

std::vector<gr_complex> test_set::observe(const pilot_mask& mask, double snr_db) const
{
    const auto idx = mask.flat_indices();
    const size_t grid = static_cast<size_t>(fs.grid_size());
    const double sigma = std::sqrt(channel_model::noise_variance(snr_db));
    // Pilot k's noise: σ/sqrt(p_k) (exactly σ for equal power).
    std::vector<float> sigma_k(idx.size());
    for (size_t k = 0; k < idx.size(); ++k)
        sigma_k[k] = static_cast<float>(sigma * mask.noise_scale(static_cast<int>(k)));
    std::vector<gr_complex> out(size_t(count) * idx.size());
    for (int f = 0; f < count; ++f)
        for (size_t k = 0; k < idx.size(); ++k) {
            const size_t at = size_t(f) * grid + size_t(idx[k]);
            out[size_t(f) * idx.size() + k] = h[at] + sigma_k[k] * w[at];
        }
    return out;
}

test_set make_test_set(const frame_settings& fs, const scene& sc, int count, uint64_t seed)
{
    test_set t;
    t.fs = fs;
    t.count = count;
    const size_t n = size_t(count) * fs.grid_size();
    t.h.resize(n);
    t.w.assign(n, gr_complex(0.0f, 0.0f));
    channel_model cm(fs, sc, seed);
    t.truth = cm.generate(count, t.h.data());
    cm.add_noise(t.w.data(), n, 0.0); // CN(0, 1) from the model's own noise generator
    return t;
}

train_set make_train_set(const frame_settings& fs, const scene& sc, int count, uint64_t seed, double lo, double hi)
{
    train_set t;
    const size_t grid = fs.grid_size();
    t.y.resize(size_t(count) * grid);
    channel_model cm(fs, sc, seed);
    t.truth = cm.generate(count, t.y.data());
    t.h = t.y; // noiseless, for masks whose pilots differ in energy
    std::mt19937_64 gen(seed ^ 0x5eed);
    for (int f = 0; f < count; ++f) {
        const double snr = lo + (hi - lo) * (double(gen() >> 11) * 0x1.0p-53);
        cm.add_noise(t.y.data() + size_t(f) * grid, grid, snr);
    }
    return t;
}

std::vector<gr_complex> gather(const std::vector<gr_complex>& grids, int count, const frame_settings& fs,
                               const pilot_mask& mask, const std::vector<gr_complex>* clean)
{
    const auto idx = mask.flat_indices();
    if (!mask.equal_power() && (!clean || clean->size() != grids.size()))
        throw std::invalid_argument("gather: a mask whose pilots differ in energy needs the noiseless grids");
    std::vector<gr_complex> out(size_t(count) * idx.size());
    for (int f = 0; f < count; ++f)
        for (size_t k = 0; k < idx.size(); ++k) {
            const size_t at = size_t(f) * fs.grid_size() + idx[k];
            // Pilot k's noise: (Y - H)/sqrt(p_k); the grid as it is for equal power.
            out[size_t(f) * idx.size() + k] =
                mask.equal_power()
                    ? grids[at]
                    : (*clean)[at] + (grids[at] - (*clean)[at]) * static_cast<float>(mask.noise_scale(int(k)));
        }
    return out;
}

std::vector<int> classify_all(const bundle_decoder& dec,
                              const std::vector<gr_complex>& obs,
                              int count,
                              const std::vector<int>& ids,
                              double& us_per_frame)
{
    const int np = dec.n_pilots(), c = static_cast<int>(ids.size());
    std::vector<int> pred(count);
    dec.classify(obs.data(), std::min(count, 32)); // warm-up: first-call allocations are not per-frame cost
    const auto t0 = std::chrono::steady_clock::now();
    for (int f0 = 0; f0 < count; f0 += 256) {
        const int b = std::min(256, count - f0);
        const auto p = dec.classify(obs.data() + size_t(f0) * np, b);
        for (int i = 0; i < b; ++i) {
            const float* row = p.data() + size_t(i) * c;
            pred[f0 + i] = ids[std::max_element(row, row + c) - row];
        }
    }
    us_per_frame = 1e6 * seconds_between(t0, std::chrono::steady_clock::now()) / count;
    return pred;
}

std::vector<gr_complex> array_pilots(const channel_model& cm, const frame_realization& r, uint64_t first_symbol,
                                     const std::vector<int>& flat, std::vector<gr_complex>& h)
{
    std::vector<gr_complex> y;
    y.reserve(size_t(cm.n_elements()) * flat.size());
    for (int k = 0; k < cm.n_elements(); ++k) {
        cm.factors(r, first_symbol, k).fill(h.data());
        for (int i : flat)
            y.push_back(h[size_t(i)]);
    }
    return y;
}

scene recognition_scene(const std::string& scenario, const config& c)
{
    random_spec r; // every class of the library (the paper's three), single path
    const auto lib = class_library::find(scenario == "kinematic" ? c.exp7_class_library : c.class_library);
    if (lib->name() != class_library::paper()->name())
        r.classes.clear(); // empty: every class of the library
    std::optional<clutter_spec> clutter;
    if (scenario == "no_md")
        r.micro_doppler = false;
    else if (scenario == "clutter") {
        clutter_spec cl;
        cl.csr_db = c.clutter_csr_db;
        clutter = cl;
    } else if (scenario == "any" || scenario == "kinematic") {
        r.heading = heading_kind::any;
    } else if (scenario != "default")
        throw std::invalid_argument("unknown recognition scenario " + scenario);
    return scene::random(r, clutter, fading_kind::rayleigh, lib);
}

scene array_test_scene(const model_bundle& bundle, std::optional<track_draw_spec> tracks)
{
    random_spec rs;
    const auto lib = bundle.library ? bundle.library : class_library::paper();
    // Every class of the library, unless the bundle knows fewer (a pair's decoder) or its track
    // record was trained on fewer (a pair's track decoder over a frame bundle of every class).
    std::vector<std::string> names;
    if (static_cast<int>(bundle.class_names.size()) < lib->size())
        names = bundle.class_names;
    if (!bundle.track.is_null()) {
        const auto trained = bundle.track.value("training", nlohmann::json::object())
                                 .value("scene", nlohmann::json::object())
                                 .value("random", nlohmann::json::object())
                                 .value("classes", nlohmann::json::array());
        if (trained.is_array() && !trained.empty() && static_cast<int>(trained.size()) < lib->size())
            names = trained.get<std::vector<std::string>>();
    }
    rs.classes.clear();
    for (const auto& name : names)
        rs.classes.push_back(static_cast<target_class>(lib->id_of(name)));
    rs.heading = heading_kind::any;
    rs.azimuth_min_rad = -0.8;
    rs.azimuth_max_rad = 0.8;
    rs.tracks = tracks;
    return scene::random(rs, std::nullopt, fading_kind::rayleigh, lib);
}

scene delay_scene(int paths)
{
    random_spec r;
    r.paths_per_target = paths;
    return scene::random(r);
}

std::vector<std::string> class_names(const scene& sc)
{
    std::vector<std::string> out;
    for (int k = 0; k < sc.library().size(); ++k)
        out.push_back(sc.library().at(k).name);
    return out;
}

class_score score(const std::vector<int>& predicted, const std::vector<int>& truth, int n_classes)
{
    class_score s;
    if (truth.empty())
        return s;
    std::vector<double> tp(n_classes, 0), fp(n_classes, 0), fn(n_classes, 0);
    int correct = 0;
    for (size_t i = 0; i < truth.size(); ++i) {
        if (predicted[i] == truth[i]) {
            ++correct;
            tp[truth[i]] += 1;
        } else {
            if (predicted[i] >= 0 && predicted[i] < n_classes)
                fp[predicted[i]] += 1;
            fn[truth[i]] += 1;
        }
    }
    s.accuracy = double(correct) / truth.size();
    double f1 = 0.0;
    int present = 0;
    for (int k = 0; k < n_classes; ++k) {
        if (tp[k] + fn[k] == 0)
            continue;
        ++present;
        const double denom = 2 * tp[k] + fp[k] + fn[k];
        f1 += denom > 0 ? 2 * tp[k] / denom : 0.0;
    }
    s.macro_f1 = present ? f1 / present : 0.0;
    return s;
}

csv_file::csv_file(const std::string& path, const std::vector<std::string>& header)
    : d_path(path), d_cols(header.size()), d_out(path)
{
    if (!d_out)
        throw std::runtime_error("cannot write " + path);
    row(header);
}

void csv_file::row(const std::vector<std::string>& values)
{
    if (values.size() != d_cols)
        throw std::logic_error(d_path + ": row with " + std::to_string(values.size()) + " values, header has " +
                               std::to_string(d_cols));
    // RFC 4180: a value with a comma, quote or line break is quoted, its quotes doubled
    // (method names and notes carry commas; Python's csv module reads it back).
    for (size_t i = 0; i < values.size(); ++i) {
        const std::string& v = values[i];
        d_out << (i ? "," : "");
        if (v.find_first_of(",\"\r\n") == std::string::npos) {
            d_out << v;
            continue;
        }
        d_out << '"';
        for (char ch : v)
            d_out << (ch == '"' ? "\"\"" : std::string(1, ch));
        d_out << '"';
    }
    d_out << "\n";
    d_out.flush();
}

std::string num(double v, int precision)
{
    if (std::isinf(v))
        return v > 0 ? "inf" : "-inf";
    if (std::isnan(v))
        return "nan";
    std::ostringstream s;
    s << std::setprecision(precision) << v;
    return s.str();
}

std::vector<cost_row>& cost_rows()
{
    static std::vector<cost_row> rows;
    return rows;
}

pilot_mask full_grid_mask(const frame_settings& fs)
{
    std::vector<pilot_position> all; // every resource element off the guard subcarriers
    for (int n = 0; n < fs.n_symbols; ++n)
        for (int m : fs.usable_subcarriers())
            all.push_back({ n, m });
    return pilot_mask(fs.n_symbols, fs.n_subcarriers, all, { 1.0f, 0.0f }, { { "kind", "full_grid" } }, "full grid");
}

std::string write_mask(const config& c, const pilot_mask& mask, const std::string& name)
{
    const auto dir = fsys::path(c.out_dir) / "masks";
    fsys::create_directories(dir);
    const auto path = (dir / (name + ".json")).string();
    mask.save(path);
    return path;
}

std::vector<uint64_t> training_seeds(const config& c)
{
    std::vector<uint64_t> out;
    for (int k = 0; k < c.seeds; ++k)
        out.push_back(c.seed + uint64_t(c.first_seed + k));
    return out;
}

std::string seeded_name(const std::string& name, uint64_t train_seed)
{
    return name + "_s" + std::to_string(train_seed);
}

std::string train_seed_label(std::optional<uint64_t> train_seed)
{
    return train_seed ? std::to_string(*train_seed) : "none";
}

training_settings base_training(const config& c, task_kind task, const scene& sc, const std::string& scene_source,
                                uint64_t train_seed)
{
    training_settings s;
    s.task = task;
    s.frame = c.fs;
    s.scene_spec = sc;
    s.scene_source = scene_source;
    s.frames = c.train_frames;
    s.epochs = c.epochs;
    s.decoder_epochs = c.decoder_epochs;
    s.patience = c.patience;
    s.batch = c.batch;
    s.threads = c.threads;
    s.seed = train_seed;
    s.eval_snr_db = {};
    s.verbose = false;
    if (task == task_kind::classify) {
        // Classifiers are cheap to train, and the mask learner needs 4-6 epochs to settle its
        // pilots (docs/results/notes/learned_vs_doppler.md): their own count.
        s.epochs = c.classifier_epochs;
        s.snr_min_db = c.train_snr_min_db;
        s.snr_max_db = c.train_snr_max_db;
    } else {
        s.snr_min_db = c.delay_train_snr_min_db;
        s.snr_max_db = c.delay_train_snr_max_db;
    }
    return s;
}

training_settings hand_pattern_training(training_settings sems, const std::string& pattern)
{
    sems.mask_pattern = pattern;
    sems.epochs += sems.decoder_epochs;
    return sems;
}

namespace {

// What a cached network must have been trained with to be reused: the training record plus
// what that record leaves to bundle.json's other sections — the task, the frame, the scene
// and every decoder's settings. (Without the last, a change of e.g. the classifier's tone fit
// or MTI stage between runs reused networks trained without it.)
nlohmann::json cache_key(const training_settings& s)
{
    auto key = s.to_json();
    key.erase("command_line"); // names the run, not the network
    if (s.pilot_power == "equal")
        key.erase("pilot_power"); // the default: caches written before the setting existed stay valid
    key["task"] = task_name(s.task);
    key["frame"] = s.frame.to_json();
    key["scene"] = s.scene_spec ? s.scene_spec->to_json() : nlohmann::json("random");
    key["classifier"] = s.classifier.to_json();
    key["delay"] = s.delay.to_json();
    key["reconstruction"] = s.reconstruction.to_json();
    // As stored: JSON text has no infinity (the noiseless networks' SNR range reads back as
    // null), so compare the key after the same round trip or those never match their cache.
    return nlohmann::json::parse(key.dump());
}

} // namespace

nlohmann::json read_eval_key(const std::string& dir)
{
    std::ifstream in(fsys::path(dir) / "eval_key.json");
    nlohmann::json stored = nlohmann::json::object();
    if (!in)
        return stored;
    try {
        in >> stored;
    } catch (const std::exception&) { // a run stopped while writing it: train again
        stored = nlohmann::json::object();
    }
    return stored;
}

std::vector<int> output_classes(const model_bundle& b, const scene& sc)
{
    b.check_library(sc.library(), "sems_eval");
    std::vector<int> ids;
    for (const auto& n : b.class_names)
        ids.push_back(sc.library().id_of(n));
    return ids;
}

decoder_source train_or_load(const config& c, const std::string& name, training_settings s, std::ostream& log)
{
    decoder_source out;
    const auto dir = fsys::path(c.out_dir) / "bundles" / name;
    s.out_dir = dir.string();
    s.command_line = c.command_line + "  [sems_eval model " + name + "]";
    const auto key = cache_key(s);
    const auto key_file = dir / "eval_key.json";
    if (fsys::exists(key_file) && fsys::exists(dir / model_bundle::bundle_file)) {
        const auto stored = read_eval_key(dir.string());
        // --reuse-bundles trusts the cache even when the trainer's settings schema changed
        // since it was written (re-measuring times on the same networks).
        if (c.reuse_bundles || stored.value("key", nlohmann::json()) == key) {
            out.bundle = model_bundle::load(dir.string());
            if (c.reuse_bundles) // trusted without its key, but never on another frame than the run's
                out.bundle.frame.require_same(s.frame, "model " + name + " (--reuse-bundles, " + dir.string() + ")",
                                              "the cached bundle's frame", "the run's frame");
            out.train_seconds = stored.value("train_seconds", 0.0);
            out.origin = "cached";
            log << "[" << now_utc() << "] model " << name << ": reusing " << dir.string() << std::endl;
            return out;
        }
    }
    // On a fixed mask (a hand pattern or the full grid) every epoch trains the decoder.
    const bool fixed_mask = !s.mask_file.empty() || !s.mask_pattern.empty();
    log << "[" << now_utc() << "] model " << name << ": training (" << s.frames << " frames, "
        << (fixed_mask ? std::to_string(s.epochs) + " decoder epochs on a fixed mask"
                       : std::to_string(s.epochs) + "+" + std::to_string(s.decoder_epochs) + " epochs")
        << ", N_p " << s.n_pilots << ", objective " << s.objective << ", seed " << s.seed << ")" << std::endl;
    fsys::create_directories(dir);
    const auto t0 = std::chrono::steady_clock::now();
    const auto res = train(s, nullptr);
    out.train_seconds = seconds_between(t0, std::chrono::steady_clock::now());
    out.bundle = model_bundle::load(dir.string());
    out.origin = "trained";
    std::ofstream(key_file) << nlohmann::json{ { "key", key }, { "train_seconds", out.train_seconds } }.dump(1);
    log << "[" << now_utc() << "] model " << name << ": trained in " << num(out.train_seconds, 4) << " s"
        << std::endl;
    return out;
}

} // namespace sems_eval
