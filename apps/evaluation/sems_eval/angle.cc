// SPDX-License-Identifier: GPL-3.0-or-later
/* sems_eval experiment 9, angle part: a target's azimuth from an array's pilots, against SNR,
 * next to its Cramér–Rao bound, for one target and for two at the same range and speed.
 *
 * One target: a car (point target, unfaded: the deterministic amplitude the bound assumes; a
 * fading gain's mean bound does not exist, E[1/|α|²] = ∞ under Rayleigh) at a random range and
 * an azimuth uniform on [−0.8, 0.8] rad, seen by a half-wavelength ULA of exp9_elements elements; each element's
 * pilots at a uniform mask of exp9_np, element-major (what the pilot extractor gives), with
 * unit-variance noise drawn once per frame and scaled per SNR (the same frames at every SNR).
 * Methods: beamforming (the one-target ML estimate), Capon, MUSIC. Its bound: the
 * deterministic CRB of each frame (energy N_p |α|²/σ²), its mean over the frames; RMSE/CRB
 * compares the methods with it. The estimators use the narrowband steering vector at the
 * pilots' mean frequency, while the emulator applies each element's exact delay on every
 * subcarrier (docs/reference/arrays.md: its phase error is bounded), so a floor above the bound
 * at high SNR is what is left of that mismatch.
 * Two targets: equal-power unfaded cars at 60 m and 8 m/s (the same delay and Doppler: coherent,
 * with the phase difference their exact delays give),
 * 1.5 beamwidths apart about a random centre in [−0.5, 0.5] rad; "both found" counts the
 * frames where both azimuths are estimated within a quarter beamwidth: beamforming (two
 * peaks), Capon and MUSIC with forward–backward smoothing over subarrays of K − 2 elements.
 * With --exp9-position-bundle (one bundle, or several of one mask and array, one per training
 * seed), the learned position decoder (position_estimator: its angle network and the polish)
 * joins the one-target rows, and every method reads that mask and array instead (the same
 * frames for all). Its network alone (without the polish) is a row of its own. With several
 * bundles each one's rows carry " [seed S]".
 * Output: exp9_angle.csv (part, method, elements, n_pilots, snr_db, frames, rmse_rad, crb_rad,
 * rmse_over_crb, both_found) and exp9_angle_predictions.csv (one target: every method's estimate of every
 * frame at every SNR, with the truth and the frame's bound: paired comparisons). */
#include "eval.h"
#include <gnuradio/sems/baselines/angle_estimators.h>
#include <gnuradio/sems/core/array/array_geometry.h>
#include <gnuradio/sems/core/array/steering.h>
#include <gnuradio/sems/learning/array/position_estimator.h>
#include <algorithm>
#include <memory>
#include <cmath>
#include <random>
#include <sstream>

namespace sems_eval {

namespace {

// count frames' noiseless pilots (K·N_p each, element-major) and unit-variance noise.
struct array_frames {
    std::vector<std::vector<gr_complex>> y, w;
    std::vector<frame_realization> r;
};

array_frames draw_frames(const frame_settings& fs, channel_model& cm, const pilot_mask& mask, int count, uint64_t seed)
{
    array_frames out;
    const auto flat = mask.flat_indices();
    std::vector<gr_complex> h(size_t(fs.grid_size()));
    std::mt19937_64 g(seed);
    std::normal_distribution<float> n(0.0f, std::sqrt(0.5f));
    for (int f = 0; f < count; ++f) {
        out.r.push_back(cm.draw(uint64_t(f)));
        auto y = array_pilots(cm, out.r.back(), uint64_t(f) * fs.n_symbols, flat, h);
        std::vector<gr_complex> w;
        for (size_t i = 0; i < y.size(); ++i)
            w.emplace_back(n(g), n(g));
        out.y.push_back(std::move(y));
        out.w.push_back(std::move(w));
    }
    return out;
}

std::vector<gr_complex> at_snr(const std::vector<gr_complex>& y, const std::vector<gr_complex>& w, double sigma)
{
    std::vector<gr_complex> v(y.size());
    for (size_t i = 0; i < y.size(); ++i)
        v[i] = y[i] + float(sigma) * w[i];
    return v;
}

} // namespace

void run_angle(const config& c, std::ostream& log)
{
    if (!c.experiments.count(9) || !c.exp9_parts.count("angle"))
        return;
    const frame_settings& fs = c.fs;
    // The learned position decoders, when given (one per training seed): their mask and array,
    // which they must share, are every method's.
    std::vector<std::unique_ptr<position_estimator>> learned;
    std::vector<std::string> seed_of;
    {
        std::stringstream list(c.exp9_position_bundle);
        std::string dir;
        while (std::getline(list, dir, ','))
            if (!dir.empty()) {
                learned.push_back(std::make_unique<position_estimator>(model_bundle::load(dir), 1));
                const auto& b = learned.back()->bundle();
                const auto& training = b.position.value("training", nlohmann::json::object());
                seed_of.push_back(training.contains("seed") ? training["seed"].dump() : std::string("none"));
                const auto& first = *learned.front();
                if (!(b.mask == first.bundle().mask) || !(learned.back()->array() == first.array()))
                    throw std::invalid_argument("--exp9-position-bundle: " + dir + " has another mask or array than " +
                                                first.bundle().directory + ": the seeds of one method share both");
                for (size_t i = 0; i + 1 < seed_of.size(); ++i)
                    if (seed_of[i] == seed_of.back())
                        throw std::invalid_argument("--exp9-position-bundle: " + dir + " and " +
                                                    learned[i]->bundle().directory + " were trained with the same seed (" +
                                                    seed_of.back() + "): give one bundle per training seed");
            }
    }
    const position_estimator* lead = learned.empty() ? nullptr : learned.front().get();
    const int k = lead ? lead->n_elements() : c.exp9_elements;
    const int np = lead ? lead->n_pilots() : c.exp9_np;
    const auto a = lead ? lead->array() : array_geometry::ula(k, 0.5 * fs.wavelength_m());
    const auto mask = lead ? lead->bundle().mask : pilot_mask::uniform(fs.n_symbols, fs.n_subcarriers, np);
    const double lambda = pilot_wavelength_m(fs, mask);
    const double beamwidth = 0.886 * 2.0 / k; // a broadside λ/2 ULA's half-power beamwidth (rad)
    csv_file csv(c.out_dir + "/exp9_angle.csv",
                 { "part", "method", "elements", "n_pilots", "snr_db", "frames", "rmse_rad", "crb_rad", "rmse_over_crb",
                   "both_found" });
    csv_file predictions(c.out_dir + "/exp9_angle_predictions.csv",
                         { "snr_db", "frame", "method", "azimuth_rad", "truth_rad", "crb_rad" });
    log << "[" << now_utc() << "] experiment 9 (angle): " << k << "-element array, N_p " << np << " per element ("
        << (lead ? "the mask and array of " + c.exp9_position_bundle : std::string("a uniform mask, a half-wavelength ULA"))
        << "), " << c.exp9_frames << " frames per point" << std::endl;

    // One target.
    random_spec rs;
    rs.classes = { target_class::car };
    rs.azimuth_min_rad = -0.8;
    rs.azimuth_max_rad = 0.8;
    channel_model one(fs, scene::random(rs, std::nullopt, fading_kind::none).with_array(a), c.seed + 9001);
    const auto frames = draw_frames(fs, one, mask, c.exp9_frames, c.seed + 9002);
    const beamforming_angle_estimator bf(a, 0.0, lambda);
    const capon_angle_estimator capon(a, 0.0, lambda);
    const music_angle_estimator music(a, 0.0, lambda, 1);
    // The classical three, then each position bundle's decoder with and without the polish (named
    // by its training seed when there are several).
    std::vector<std::string> names = { "beamforming", "Capon", "MUSIC" };
    for (size_t b = 0; b < learned.size(); ++b) {
        const std::string tag = learned.size() > 1 ? " [seed " + seed_of[b] + "]" : "";
        names.push_back("SemS position (learned)" + tag);
        names.push_back("SemS angle network (no polish)" + tag);
    }
    const int methods = static_cast<int>(names.size());
    for (double snr : c.exp9_snrs) {
        const double sigma2 = std::pow(10.0, -snr / 10.0);
        double crb = 0.0;
        std::vector<double> se(size_t(methods), 0.0), est(size_t(methods), 0.0);
        for (int f = 0; f < c.exp9_frames; ++f) {
            const auto& p = frames.r[size_t(f)].paths[0];
            const auto y = at_snr(frames.y[size_t(f)], frames.w[size_t(f)], std::sqrt(sigma2));
            const double az = p.azimuth_rad;
            const double bound = angle_crb_rad2(a, az, 0.0, lambda, std::max(np * std::norm(p.gain) / sigma2, 1e-300));
            crb += bound;
            est[0] = bf.estimate(y.data(), np)[0];
            est[1] = capon.estimate(y.data(), np)[0];
            est[2] = music.estimate(y.data(), np)[0];
            for (size_t b = 0; b < learned.size(); ++b) {
                est[3 + 2 * b] = learned[b]->estimate_azimuth(y.data(), 1, true)[0];
                est[4 + 2 * b] = learned[b]->estimate_azimuth(y.data(), 1, false)[0];
            }
            for (int m = 0; m < methods; ++m) {
                se[size_t(m)] += (est[size_t(m)] - az) * (est[size_t(m)] - az);
                predictions.row({ num(snr), std::to_string(f), names[size_t(m)], num(est[size_t(m)], 9), num(az, 9),
                                  num(std::sqrt(bound), 6) });
            }
        }
        const double crb_rad = std::sqrt(crb / c.exp9_frames);
        for (int m = 0; m < methods; ++m) {
            const double rmse = std::sqrt(se[size_t(m)] / c.exp9_frames);
            csv.row({ "one_target", names[size_t(m)], std::to_string(k), std::to_string(np), num(snr), std::to_string(c.exp9_frames),
                      num(rmse), num(crb_rad), num(rmse / crb_rad), "" });
            log << "  one target " << names[size_t(m)] << " snr " << snr << ": RMSE " << num(rmse, 4) << " rad (CRB "
                << num(crb_rad, 4) << ", x" << num(rmse / crb_rad, 3) << ")" << std::endl;
        }
    }

    // Two coherent targets 1.5 beamwidths apart.
    const int sub = k - 2;
    const capon_angle_estimator capon_fb(a, 0.0, lambda, 1e-3, sub);
    const music_angle_estimator music_fb(a, 0.0, lambda, 2, sub);
    std::mt19937_64 g(c.seed + 9003);
    std::uniform_real_distribution<double> centre(-0.5, 0.5);
    std::vector<double> centres(size_t(c.exp9_frames));
    std::vector<array_frames> pairs;
    for (int f = 0; f < c.exp9_frames; ++f) {
        centres[size_t(f)] = centre(g);
        std::vector<target_spec> ts(2);
        for (int i = 0; i < 2; ++i) {
            ts[size_t(i)].cls = target_class::car;
            ts[size_t(i)].range_m = 60.0;
            ts[size_t(i)].velocity_mps = 8.0;
            ts[size_t(i)].azimuth_rad = centres[size_t(f)] + (i ? 0.75 : -0.75) * beamwidth;
        }
        channel_model cm(fs, scene::fixed(ts, std::nullopt, 0, fading_kind::none).with_array(a), c.seed + 9100 + uint64_t(f));
        pairs.push_back(draw_frames(fs, cm, mask, 1, c.seed + 9200 + uint64_t(f)));
    }
    for (double snr : c.exp9_snrs) {
        const double sigma = std::pow(10.0, -snr / 20.0);
        int hits[3] = { 0, 0, 0 };
        for (int f = 0; f < c.exp9_frames; ++f) {
            const auto y = at_snr(pairs[size_t(f)].y[0], pairs[size_t(f)].w[0], sigma);
            const double lo = centres[size_t(f)] - 0.75 * beamwidth, hi = centres[size_t(f)] + 0.75 * beamwidth;
            auto both = [&](std::vector<double> e) {
                if (e.size() != 2)
                    return 0;
                std::sort(e.begin(), e.end());
                return int(std::fabs(e[0] - lo) < 0.25 * beamwidth && std::fabs(e[1] - hi) < 0.25 * beamwidth);
            };
            hits[0] += both(bf.estimate(y.data(), np, 2));
            hits[1] += both(capon_fb.estimate(y.data(), np, 2));
            hits[2] += both(music_fb.estimate(y.data(), np));
        }
        const char* pair_names[3] = { "beamforming", "Capon (smoothed)", "MUSIC (smoothed)" };
        for (int m = 0; m < 3; ++m) {
            const double rate = double(hits[m]) / c.exp9_frames;
            csv.row({ "two_targets", pair_names[m], std::to_string(k), std::to_string(np), num(snr),
                      std::to_string(c.exp9_frames), "", "", "", num(rate) });
            log << "  two targets " << pair_names[m] << " snr " << snr << ": both found in " << num(100 * rate, 3)
                << " % of frames" << std::endl;
        }
    }
    log << "[" << now_utc() << "] experiment 9 (angle) done: " << csv.path() << std::endl;
}

} // namespace sems_eval
