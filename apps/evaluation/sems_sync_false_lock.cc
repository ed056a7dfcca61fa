// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: sems_sync_false_lock — how often frame_search locks on noise, and how often it
 * finds the frame at a low SNR, with and without the transmitter's leakage.
 *
 * Noise: a stream of complex white Gaussian noise searched as frame_sync searches it (a
 * window of F + 1 frames, one search per frame, the window sliding by a frame): counts the
 * searches whose metric passes the threshold (false locks), and the exceedances of lower
 * levels, each beside frame_search::false_lock_probability() (the null model).
 * Detection: frames of the mask's pilots and random QPSK data, started at a random sample of
 * the window; the echo (unit power per resource element, a random delay of 0 .. max-delay
 * samples, a random phase every frame: a moving target) in noise at --snr-db per resource
 * element, with and without the leakage (the transmitted samples at --leakage-db over the
 * echo, delay 0). A detection is a lock on the right sample: the frame start with leakage
 * (it times from the leakage), the frame start plus the echo's delay without.
 * Exits 1 when --max-false-locks is exceeded or a detection rate is under --min-leakage-detection
 * (with leakage) or --min-echo-detection (the echo alone).
 */
#include <gnuradio/sems/core/frame/frame_search.h>
#include <gnuradio/sems/core/frame/ofdm_modem.h>
#include <gnuradio/sems/core/frame/pilot_mask.h>
#include <boost/program_options.hpp>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <random>
#include <vector>

namespace po = boost::program_options;
using namespace gr::sems;

namespace {

struct options {
    std::string mask;
    int cp = 16, search_frames = 4, max_delay = 40;
    double pilot_power = 1.0, threshold = 0.0, snr_db = 0.0, leakage_db = 40.0;
    double min_leakage = 0.0, min_echo = 0.0; // least detection rates accepted
    bool noncoherent = false;
    long noise_frames = 100000, trials = 1000, report = 10000, max_false_locks = -1;
    unsigned seed = 1;
};

// CP-OFDM frames of the mask's pilots (as the mapper sends them) and unit QPSK data.
class frame_maker
{
public:
    frame_maker(const pilot_mask& mask, int cp, double pilot_power)
        : d_n(mask.n_symbols()), d_m(mask.n_subcarriers()), d_modem(mask.n_subcarriers(), cp),
          d_x(size_t(mask.n_subcarriers())), d_rows(mask.carrier_lists()), d_values(mask.pilot_symbol_lists()),
          d_ep(std::sqrt(pilot_power))
    {
    }
    int len() const { return d_n * d_modem.symbol_len(); }
    void make(std::mt19937_64& g, gr_complex* out)
    {
        const float q = float(M_SQRT1_2);
        for (int k = 0; k < d_n; ++k) {
            for (int i = 0; i < d_m; ++i)
                d_x[size_t(i)] = gr_complex((g() & 1) ? q : -q, (g() & 2) ? q : -q);
            for (size_t j = 0; j < d_rows[k].size(); ++j)
                d_x[size_t(d_rows[k][j])] = d_values[k][j] * float(d_ep);
            d_modem.modulate(d_x.data(), out + size_t(k) * d_modem.symbol_len());
        }
    }

private:
    int d_n, d_m;
    ofdm_modem d_modem;
    std::vector<gr_complex> d_x; // one symbol's subcarrier values
    std::vector<std::vector<int>> d_rows;
    std::vector<std::vector<gr_complex>> d_values;
    double d_ep;
};

void add_noise(std::mt19937_64& g, gr_complex* x, size_t n, double sigma2)
{
    std::normal_distribution<float> d(0.0f, float(std::sqrt(sigma2 / 2.0)));
    for (size_t i = 0; i < n; ++i)
        x[i] += gr_complex(d(g), d(g));
}

// Noise alone, searched frame by frame as frame_sync does; returns the false locks.
long false_locks(const options& o, const frame_search& fs)
{
    const size_t L = size_t(fs.frame_len()), w = size_t(fs.window_len());
    // Lower levels, where the null model's tail is measurable: those it puts at 1e-1 .. 1e-4.
    std::vector<double> levels;
    for (double p : { 1e-1, 1e-2, 1e-3, 1e-4 })
        levels.push_back(frame_search::threshold_for(p, o.search_frames, fs.frame_len(), fs.noncoherent()));
    levels.push_back(fs.threshold());
    std::vector<long> over(levels.size(), 0);
    std::mt19937_64 g(o.seed);
    std::vector<gr_complex> x(w, gr_complex(0.0f, 0.0f));
    add_noise(g, x.data(), w, 1.0);
    long locks = 0;
    for (long f = 1; f <= o.noise_frames; ++f) {
        const auto r = fs.search(x.data());
        locks += r.found ? 1 : 0;
        for (size_t i = 0; i < levels.size(); ++i)
            over[i] += r.metric > levels[i] ? 1 : 0;
        std::copy(x.begin() + std::ptrdiff_t(L), x.end(), x.begin()); // slide by a frame
        std::fill(x.end() - std::ptrdiff_t(L), x.end(), gr_complex(0.0f, 0.0f));
        add_noise(g, x.data() + (w - L), L, 1.0);
        if (o.report > 0 && f % o.report == 0)
            std::fprintf(stderr, "noise: %ld / %ld searches, %ld false locks\n", f, o.noise_frames, locks);
    }
    std::printf("noise: %ld searches (one per frame), threshold %.3f: %ld false locks (predicted %.3g per search)\n",
                o.noise_frames, fs.threshold(), locks,
                frame_search::false_lock_probability(fs.threshold(), o.search_frames, fs.frame_len(), fs.noncoherent()));
    std::printf("  level   exceedances  rate        predicted\n");
    for (size_t i = 0; i < levels.size(); ++i)
        std::printf("  %6.2f  %11ld  %-10.3g  %.3g\n", levels[i], over[i], double(over[i]) / double(o.noise_frames),
                    frame_search::false_lock_probability(levels[i], o.search_frames, fs.frame_len(), fs.noncoherent()));
    return locks;
}

// Frames at a random start, echo (+ leakage) in noise; returns the rate of locks on the right sample.
double detection(const options& o, const frame_search& fs, frame_maker& fm, bool leakage)
{
    const size_t L = size_t(fs.frame_len()), w = size_t(fs.window_len());
    const int frames = o.search_frames + 2;
    std::mt19937_64 g(o.seed + (leakage ? 7 : 3));
    std::uniform_int_distribution<int> start(0, int(L) - 1), delay(0, o.max_delay);
    std::uniform_real_distribution<float> phase(0.0f, float(2.0 * M_PI));
    const double sigma2 = std::pow(10.0, -o.snr_db / 10.0);
    const float lk = float(std::pow(10.0, o.leakage_db / 20.0));
    std::vector<gr_complex> tx(size_t(frames) * L), rx(tx.size());
    long right = 0, wrong = 0;
    for (long t = 0; t < o.trials; ++t) {
        for (int f = 0; f < frames; ++f)
            fm.make(g, tx.data() + size_t(f) * L);
        const int d = delay(g), theta = start(g);
        std::fill(rx.begin(), rx.end(), gr_complex(0.0f, 0.0f));
        for (int f = 0; f < frames; ++f) {
            const gr_complex a = std::polar(1.0f, phase(g)); // the echo's phase this frame
            for (size_t i = 0; i < L; ++i) {
                const size_t n = size_t(f) * L + i;
                if (n >= size_t(d))
                    rx[n] += a * tx[n - size_t(d)];
                if (leakage)
                    rx[n] += lk * tx[n];
            }
        }
        add_noise(g, rx.data(), rx.size(), sigma2);
        // The window starts L − θ samples in: frame 1 starts at θ.
        const auto r = fs.search(rx.data() + (L - size_t(theta)));
        const long expect = theta + (leakage ? 0 : d);
        if (r.found && (long(r.lag) - expect) % long(L) == 0)
            ++right;
        else if (r.found)
            ++wrong;
        if (o.report > 0 && (t + 1) % (o.report / 10 > 0 ? o.report / 10 : 1) == 0)
            std::fprintf(stderr, "detection (%s leakage): %ld / %ld trials\n", leakage ? "with" : "without", t + 1,
                         o.trials);
    }
    (void)w;
    const double rate = double(right) / double(o.trials);
    std::printf("detection at %.1f dB per resource element, %s leakage%s: %ld / %ld on the right sample (%.4f), "
                "%ld on a wrong one\n",
                o.snr_db, leakage ? "with" : "without",
                leakage ? (" (" + std::to_string(int(o.leakage_db)) + " dB over the echo)").c_str() : "", right,
                o.trials, rate, wrong);
    return rate;
}

} // namespace

int main(int argc, char** argv)
{
    options o;
    po::options_description desc("sems_sync_false_lock: frame_search's false locks on noise and its detections");
    desc.add_options()("help,h", "this help")(
        "mask", po::value(&o.mask)->required(), "pilot-mask JSON of the transmitter")(
        "cp", po::value(&o.cp)->default_value(o.cp), "cyclic prefix (samples)")(
        "pilot-power", po::value(&o.pilot_power)->default_value(o.pilot_power), "E_p of the transmitter")(
        "search-frames", po::value(&o.search_frames)->default_value(o.search_frames), "F, frames per search")(
        "noncoherent", po::bool_switch(&o.noncoherent), "combine the F frames in power")(
        "threshold", po::value(&o.threshold)->default_value(o.threshold),
        "threshold on the metric; 0: frame_search::threshold_for(1e-6) of the combining")(
        "noise-frames", po::value(&o.noise_frames)->default_value(o.noise_frames), "frames of noise (searches)")(
        "trials", po::value(&o.trials)->default_value(o.trials), "detection trials, each with and without leakage")(
        "snr-db", po::value(&o.snr_db)->default_value(o.snr_db), "echo SNR per resource element (dB)")(
        "leakage-db", po::value(&o.leakage_db)->default_value(o.leakage_db), "leakage over the echo (dB)")(
        "max-delay", po::value(&o.max_delay)->default_value(o.max_delay), "echo delay drawn in 0 .. this (samples)")(
        "seed", po::value(&o.seed)->default_value(o.seed), "random seed")(
        "report", po::value(&o.report)->default_value(o.report), "progress every this many noise searches, and every tenth of it in the detection trials (0: none)")(
        "max-false-locks", po::value(&o.max_false_locks)->default_value(o.max_false_locks),
        "exit 1 above this many false locks (-1: no check)")(
        "min-leakage-detection", po::value(&o.min_leakage)->default_value(o.min_leakage),
        "exit 1 when the detection rate with leakage is below this")(
        "min-echo-detection", po::value(&o.min_echo)->default_value(o.min_echo),
        "exit 1 when the detection rate of the echo alone is below this");
    try {
        po::variables_map vm;
        po::store(po::parse_command_line(argc, argv, desc), vm);
        if (vm.count("help")) {
            std::cout << desc << "\n";
            return 0;
        }
        po::notify(vm);
        if (o.noise_frames < 0 || o.trials < 0)
            throw std::invalid_argument("--noise-frames and --trials must be >= 0");
        if (o.max_delay < 0)
            throw std::invalid_argument("--max-delay must be >= 0, got " + std::to_string(o.max_delay));
        const auto mask = pilot_mask::load(o.mask);
        const int L = mask.n_symbols() * (mask.n_subcarriers() + o.cp);
        if (o.threshold == 0.0)
            o.threshold = frame_search::threshold_for(1e-6, o.search_frames, L, o.noncoherent);
        const frame_search fs(mask, o.cp, o.pilot_power, o.search_frames, o.threshold, o.noncoherent);
        std::printf("sems_sync_false_lock: %s, L = %d samples, F = %d, %s combining, threshold %.3f\n", o.mask.c_str(),
                    L, o.search_frames, o.noncoherent ? "non-coherent" : "coherent", o.threshold);
        frame_maker fm(mask, o.cp, o.pilot_power);
        bool ok = true;
        if (o.noise_frames > 0) {
            const long locks = false_locks(o, fs);
            ok = ok && (o.max_false_locks < 0 || locks <= o.max_false_locks);
        }
        if (o.trials > 0)
            for (bool leakage : { true, false })
                ok = detection(o, fs, fm, leakage) >= (leakage ? o.min_leakage : o.min_echo) && ok;
        std::printf("sems_sync_false_lock: %s\n", ok ? "pass" : "FAIL");
        return ok ? 0 : 1;
    } catch (const std::exception& e) {
        std::cerr << "sems_sync_false_lock: " << e.what() << "\n";
        return 2;
    }
}
