// SPDX-License-Identifier: GPL-3.0-or-later
/* sems_eval: kept per-frame predictions and the test frames' truth, beside the CSVs, for the
 * paired statistics of apps/figures/paired_stats.py (docs/reference/file_formats.md, "Kept
 * predictions"). Each file is a NumPy .npz archive (a zip of .npy arrays, stored without
 * compression, no time stamps, so the same run writes the same bytes) that numpy.load reads
 * without pickles:
 *
 *   <csv stem>_predictions.npz   info (1 record), series (one record per kept series: scenario,
 *                                method, mask, n_pilots, snr_db, train_seed (-1: none),
 *                                test_seed), values (one row per series: class ids + 1 packed in
 *                                `bits` bits per frame, most significant bit first, each row
 *                                padded to a whole byte; or delay-index errors as float32)
 *   exp<N>_truth.npz             info, scenarios (scenario, test_seed, n_frames), and per scenario
 *                                frames_<scenario> (frame, class_id, delay_index, range_m,
 *                                velocity_mps) and classes_<scenario> (class_id, name)
 *
 * The archive writer is predictions.cc. */
#ifndef SEMS_EVAL_PREDICTIONS_H
#define SEMS_EVAL_PREDICTIONS_H

#include <gnuradio/sems/core/channel/channel_model.h>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace sems_eval {


// The name of a kept-predictions file: <out>/<csv stem>_predictions.npz.
inline std::string predictions_path(const std::string& out_dir, const std::string& csv_stem)
{
    return out_dir + "/" + csv_stem + "_predictions.npz";
}

// One series: a method on one operating point, as its CSV row names it.
struct series_key {
    std::string scenario, method, mask;
    int n_pilots = 0;
    double snr_db = 0.0;
    std::optional<uint64_t> train_seed; // none: a method without training
    uint64_t test_seed = 0;
};

// The per-frame outputs behind one CSV: class ids (experiments 1, 3, 7 and 9's classes part) or delay-index
// errors, estimate minus truth, as float32 (experiments 4 and 5). The file is rewritten
// whole by write(): call it after each method, so a stopped run keeps what it scored.
class kept_predictions
{
public:
    enum class kind { class_id, delay_index };

    // A file of an earlier run at `path` is removed: until the first write() there is none,
    // rather than one that does not match the CSV being written.
    kept_predictions(std::string path, std::string experiment, kind k)
        : d_path(std::move(path)), d_experiment(std::move(experiment)), d_kind(k)
    {
        std::remove(d_path.c_str());
    }

    // Class ids in [0, n_classes) or -1 (no decision); n_classes is the scene's library size.
    void add(const series_key& key, const std::vector<int>& ids, int n_classes)
    {
        if (d_kind != kind::class_id)
            throw std::logic_error("kept predictions: class ids in a file of delay errors");
        for (int id : ids)
            if (id < -1 || id >= n_classes)
                throw std::logic_error("kept predictions: class id " + std::to_string(id) + " outside [-1, " +
                                       std::to_string(n_classes) + ") for " + key.method);
        d_classes = std::max(d_classes, n_classes);
        check_frames(key, ids.size());
        d_keys.push_back(key);
        d_ids.emplace_back(ids.begin(), ids.end());
    }

    // Delay-index errors (estimate minus the true delay index), as scored.
    void add(const series_key& key, const std::vector<float>& errors)
    {
        if (d_kind != kind::delay_index)
            throw std::logic_error("kept predictions: delay errors in a file of class ids");
        check_frames(key, errors.size());
        d_keys.push_back(key);
        d_errors.push_back(errors);
    }

    // Bits per packed class id: enough for n_classes + 1 values (id + 1, so -1 is 0).
    int bits() const
    {
        int b = 1;
        while ((1 << b) < d_classes + 1)
            ++b;
        return b;
    }

    void write() const;

    const std::string& path() const { return d_path; }

private:
    void check_frames(const series_key& key, size_t n)
    {
        if (d_keys.empty())
            d_frames = n;
        else if (n != d_frames)
            throw std::logic_error("kept predictions: " + key.method + " has " + std::to_string(n) +
                                   " frames, the file's series " + std::to_string(d_frames));
    }

    std::string d_path, d_experiment;
    kind d_kind;
    int d_classes = 1;
    size_t d_frames = 0;
    std::vector<series_key> d_keys;
    std::vector<std::vector<int16_t>> d_ids;
    std::vector<std::vector<float>> d_errors;
};

// The test frames of one experiment, one entry per scenario (what identifies a frame: its
// scenario, the test seed and its index; then its truth). Written at once by add().
class truth_file
{
public:
    truth_file(std::string path, std::string experiment) : d_path(std::move(path)), d_experiment(std::move(experiment))
    {
    }

    void add(const std::string& scenario, uint64_t test_seed, const std::vector<gr::sems::frame_truth>& truth,
             const std::vector<std::string>& class_names)
    {
        for (const auto& s : d_scenarios)
            if (s.name == scenario)
                throw std::logic_error("kept predictions: scenario " + scenario + " twice in " + d_path);
        d_scenarios.push_back({ scenario, test_seed, truth, class_names });
        write();
    }

private:
    struct entry {
        std::string name;
        uint64_t test_seed;
        std::vector<gr::sems::frame_truth> truth;
        std::vector<std::string> classes;
    };

    void write() const;

    std::string d_path, d_experiment;
    std::vector<entry> d_scenarios;
};

} // namespace sems_eval

#endif
