// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: pilot masks — patterns, file round trip, validation. */
#include <gnuradio/sems/core/frame/pilot_mask.h>
#include "qa/qa_assert.h"
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <cmath>
#include <complex>
#include <cstdio>
#include <limits>
#include <numeric>
#include <algorithm>
#include <map>
#include <set>
#include <string>

using namespace gr::sems;
using gr::sems::qa::assert_error;

namespace {
// Asserts that `f` throws std::invalid_argument whose message contains `needle`.

// Crest factor (peak over rms of the magnitude) of symbol n's pilots in the time domain as the
// transmitter sends it, x(t) = Σ_k v_k exp(j2π f_k t/M) at t = i/oversample,
// i = 0..M·oversample−1, with f_k = m_k for m_k < M/2 and m_k − M above (bin m ≥ M/2 is a
// negative frequency, docs/reference/frame_files.md): oversample 1 is what an M-point IFFT gives
// (the same for either sign), more looks between its samples.
double crest_factor(const pilot_mask& mk, int n, int oversample)
{
    const int m = mk.n_subcarriers(), len = m * oversample;
    double peak = 0.0, energy = 0.0;
    for (int i = 0; i < len; ++i) {
        std::complex<double> x = 0.0;
        for (int k = 0; k < mk.size(); ++k)
            if (mk.positions()[k].n == n)
                x += std::complex<double>(mk.transmitted_pilot(k)) *
                     std::polar(1.0, 2.0 * M_PI * (mk.positions()[k].m < m / 2 ? mk.positions()[k].m : mk.positions()[k].m - m) *
                                         double(i) / double(len));
        peak = std::max(peak, std::abs(x));
        energy += std::norm(x);
    }
    return peak / std::sqrt(energy / len);
}

// pilot_mask::random(1, M, K, seed)'s subcarriers on symbol `row` of an N x M frame: how
// models/delay_single/mask.json was made (K = 32, M = 64, seed 1, symbol 16).
pilot_mask one_symbol(int n, int m, int k, uint64_t seed, int row)
{
    const auto drawn = pilot_mask::random(1, m, k, seed);
    std::vector<pilot_position> pos;
    for (const auto& p : drawn.positions())
        pos.push_back({ row, p.m });
    return pilot_mask(n, m, pos);
}

// The mask written to `path` and read back (the file removed).
pilot_mask through_file(const pilot_mask& mk, const std::string& path)
{
    mk.save(path);
    auto back = pilot_mask::load(path);
    std::remove(path.c_str());
    return back;
}

// The allocator's per-symbol lists (what the time-domain transmitter and the templates use)
// hold transmitted_pilot(k) in mask order: for the round-trip masks, pilots 0 and 1 on
// symbol 0 and pilot 3 on symbol 2.
void check_lists(const pilot_mask& mk)
{
    const auto lists = mk.pilot_symbol_lists();
    CPPUNIT_ASSERT(lists[0][0] == mk.transmitted_pilot(0) && lists[0][1] == mk.transmitted_pilot(1));
    CPPUNIT_ASSERT(lists[2][0] == mk.transmitted_pilot(3));
}

std::string mask_text(const std::string& pilots, int n = 4, int m = 8, const std::string& extra = "")
{
    return R"({"format": "sems.pilot_mask", "version": 1, "n_symbols": )" + std::to_string(n) +
           R"(, "n_subcarriers": )" + std::to_string(m) + R"(, "pilot_symbol": [1.0, 0.0], "pilots": )" + pilots +
           extra + "}";
}
} // namespace

class qa_pilot_mask : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_pilot_mask);
    CPPUNIT_TEST(uniform_lattice);
    CPPUNIT_TEST(doppler_pattern);
    CPPUNIT_TEST(staggered_spans_band_at_every_symbol);
    CPPUNIT_TEST(burst_is_a_centred_run_of_symbols);
    CPPUNIT_TEST(random_is_seeded);
    CPPUNIT_TEST(count_extremes);
    CPPUNIT_TEST(mask_order_and_exports);
    CPPUNIT_TEST(file_round_trip);
    CPPUNIT_TEST(bad_masks_are_refused);
    CPPUNIT_TEST(power_round_trip);
    CPPUNIT_TEST(bad_power_is_refused);
    CPPUNIT_TEST(phases_round_trip);
    CPPUNIT_TEST(newman_crest_factor);
    CPPUNIT_TEST(bad_phases_are_refused);
    CPPUNIT_TEST_SUITE_END();

public:
    void uniform_lattice()
    {
        auto mk = pilot_mask::uniform(32, 64, 32); // 4 rows x 8 columns, spacing 8 x 8
        CPPUNIT_ASSERT_EQUAL(32, mk.size());
        std::set<int> rows, cols;
        for (const auto& p : mk.positions()) {
            rows.insert(p.n);
            cols.insert(p.m);
        }
        CPPUNIT_ASSERT(rows == (std::set<int>{ 4, 12, 20, 28 }));
        CPPUNIT_ASSERT(cols == (std::set<int>{ 4, 12, 20, 28, 36, 44, 52, 60 }));
        CPPUNIT_ASSERT_EQUAL(std::string("uniform"), mk.origin()["kind"].get<std::string>());
    }

    void doppler_pattern()
    {
        auto mk = pilot_mask::doppler(32, 64, 32); // one subcarrier over every symbol
        std::set<int> cols;
        for (const auto& p : mk.positions())
            cols.insert(p.m);
        CPPUNIT_ASSERT_EQUAL(size_t(1), cols.size());
        auto two = pilot_mask::doppler(32, 64, 48); // two subcarriers, 24 symbols each
        std::set<int> cols2;
        for (const auto& p : two.positions())
            cols2.insert(p.m);
        CPPUNIT_ASSERT_EQUAL(size_t(2), cols2.size());
    }

    void burst_is_a_centred_run_of_symbols()
    {
        // 8 pilots: symbols 12..19 of the Doppler pattern's one subcarrier (32), in a row.
        const auto m8 = pilot_mask::burst(32, 64, 8);
        std::vector<int> symbols;
        for (const auto& p : m8.positions()) {
            CPPUNIT_ASSERT_EQUAL(pilot_mask::doppler(32, 64, 8).positions()[0].m, p.m);
            symbols.push_back(p.n);
        }
        CPPUNIT_ASSERT(symbols == (std::vector<int>{ 12, 13, 14, 15, 16, 17, 18, 19 }));
        // An odd run and an odd frame: 5 of 9 symbols are 2..6.
        const auto odd = pilot_mask::burst(9, 4, 5);
        CPPUNIT_ASSERT_EQUAL(2, odd.positions().front().n);
        CPPUNIT_ASSERT_EQUAL(6, odd.positions().back().n);
        // Whole columns: the Doppler pattern itself; 40 pilots: 20 + 20 in the middle.
        CPPUNIT_ASSERT(pilot_mask::burst(32, 64, 64).flat_indices() == pilot_mask::doppler(32, 64, 64).flat_indices());
        const auto m40 = pilot_mask::burst(32, 64, 40);
        std::map<int, std::vector<int>> by_col;
        for (const auto& p : m40.positions())
            by_col[p.m].push_back(p.n);
        CPPUNIT_ASSERT_EQUAL(size_t(2), by_col.size());
        for (const auto& [col, rows] : by_col) {
            CPPUNIT_ASSERT_EQUAL(size_t(20), rows.size());
            CPPUNIT_ASSERT_EQUAL(6, *std::min_element(rows.begin(), rows.end()));
            CPPUNIT_ASSERT_EQUAL(25, *std::max_element(rows.begin(), rows.end()));
        }
        CPPUNIT_ASSERT_EQUAL(std::string("burst"), m40.origin().value("kind", std::string()));
        CPPUNIT_ASSERT(pilot_mask::from_pattern("burst", 32, 64, 8).flat_indices() == m8.flat_indices());
        CPPUNIT_ASSERT_THROW(pilot_mask::burst(32, 64, 0), std::invalid_argument);
        CPPUNIT_ASSERT_THROW(pilot_mask::burst(32, 64, 32 * 64 + 1), std::invalid_argument);
    }

    void staggered_spans_band_at_every_symbol()
    {
        // 32 pilots: band edges 0 and 63 alternating, one pilot per symbol.
        const auto m32 = pilot_mask::staggered(32, 64, 32);
        for (const auto& p : m32.positions())
            CPPUNIT_ASSERT_EQUAL(p.n % 2 == 0 ? 0 : 63, p.m);
        // 128 pilots: 4 per symbol on alternating halves of 8 subcarriers 0, 9, ..., 63.
        const auto m128 = pilot_mask::staggered(32, 64, 128);
        std::map<int, std::set<int>> by_symbol;
        for (const auto& p : m128.positions())
            by_symbol[p.n].insert(p.m);
        CPPUNIT_ASSERT_EQUAL(size_t(32), by_symbol.size());
        CPPUNIT_ASSERT(by_symbol[0] == (std::set<int>{ 0, 9, 18, 27 }));
        CPPUNIT_ASSERT(by_symbol[1] == (std::set<int>{ 36, 45, 54, 63 }));
        // Fewer pilots than symbols: evenly spread symbols, still both edges.
        const auto m8 = pilot_mask::staggered(32, 64, 8);
        std::set<int> cols, rows;
        for (const auto& p : m8.positions()) {
            cols.insert(p.m);
            rows.insert(p.n);
        }
        CPPUNIT_ASSERT(cols == (std::set<int>{ 0, 63 }));
        CPPUNIT_ASSERT_EQUAL(size_t(8), rows.size());
        CPPUNIT_ASSERT_EQUAL(std::string("staggered"), m8.origin().value("kind", std::string()));
    }

    void random_is_seeded()
    {
        CPPUNIT_ASSERT(pilot_mask::random(32, 64, 32, 7) == pilot_mask::random(32, 64, 32, 7));
        CPPUNIT_ASSERT(!(pilot_mask::random(32, 64, 32, 7) == pilot_mask::random(32, 64, 32, 8)));
    }

    void count_extremes()
    {
        for (const char* pattern : { "uniform", "random", "doppler", "staggered" }) {
            CPPUNIT_ASSERT_EQUAL(1, pilot_mask::from_pattern(pattern, 32, 64, 1, 3).size());
            auto all = pilot_mask::from_pattern(pattern, 32, 64, 32 * 64, 3);
            CPPUNIT_ASSERT_EQUAL(32 * 64, all.size()); // every resource element, no duplicates
            for (int c : { 0, 32 * 64 + 1 })
                assert_error([&] { pilot_mask::from_pattern(pattern, 32, 64, c, 3); }, "count must be in");
        }
        for (int c : { 2, 7, 31, 33, 100, 1000, 2047 }) // awkward counts still exact
            CPPUNIT_ASSERT_EQUAL(c, pilot_mask::uniform(32, 64, c).size());
    }

    void mask_order_and_exports()
    {
        pilot_mask mk(4, 8, { { 3, 1 }, { 0, 7 }, { 0, 2 }, { 2, 5 } }, gr_complex(0.0f, 2.0f));
        const std::vector<int> flat = { 2, 7, 21, 25 }; // sorted by (n, m)
        CPPUNIT_ASSERT(mk.flat_indices() == flat);
        auto lists = mk.carrier_lists();
        CPPUNIT_ASSERT_EQUAL(size_t(4), lists.size());
        CPPUNIT_ASSERT(lists[0] == (std::vector<int>{ 2, 7 }));
        CPPUNIT_ASSERT(lists[1].empty());
        CPPUNIT_ASSERT(lists[3] == (std::vector<int>{ 1 }));
        CPPUNIT_ASSERT(mk.pilot_symbol_lists()[0][1] == gr_complex(0.0f, 2.0f));
        auto dense = mk.dense();
        CPPUNIT_ASSERT_EQUAL(4, std::accumulate(dense.begin(), dense.end(), 0));
    }

    void file_round_trip()
    {
        auto mk = pilot_mask::random(32, 64, 32, 11);
        const std::string path = "qa_pilot_mask_roundtrip.json";
        mk.save(path);
        auto back = pilot_mask::load(path);
        std::remove(path.c_str());
        CPPUNIT_ASSERT(mk == back);
        CPPUNIT_ASSERT_EQUAL(std::string("random"), back.origin()["kind"].get<std::string>());
        CPPUNIT_ASSERT(pilot_mask::parse(mk.to_json_string()) == mk);
    }

    void bad_masks_are_refused()
    {
        assert_error([] { pilot_mask::parse(mask_text("[[0, 1], [0, 1]]"), "dup.json"); }, "dup.json: pilots: duplicate");
        assert_error([] { pilot_mask::parse(mask_text("[[4, 1]]"), "oob.json"); }, "outside the 4 x 8 grid");
        assert_error([] { pilot_mask::parse(mask_text("[[0, -1]]"), "neg.json"); }, "outside");
        assert_error([] { pilot_mask::parse(mask_text("[[0, 1]]", 0, 8), "dims.json"); }, "n_symbols: must be in [1, 65536], got 0");
        assert_error([] { pilot_mask::parse(mask_text("[[0, 1]]", 4, 8, R"(, "n_pilots": 2)"), "cnt.json"); },
                     "declares 2 pilots but the list has 1");
        assert_error([] { pilot_mask::parse(mask_text("[]"), "empty.json"); }, "at least one pilot");
        assert_error([] { pilot_mask::parse(mask_text("[[0, 1.5]]"), "frac.json"); }, "expected an integer");
        assert_error([] { pilot_mask::parse(mask_text("[[0, 1, 2]]"), "tri.json"); }, "expected [n, m]");
        assert_error([] { pilot_mask::parse("{not json", "broken.json"); }, "broken.json: not valid JSON");
        assert_error([] { pilot_mask::parse(R"({"format": "other", "version": 1})", "fmt.json"); }, "format");
        assert_error([] { pilot_mask::load("/nonexistent/mask.json"); }, "/nonexistent/mask.json: cannot open");
        assert_error([] { pilot_mask(2, 2, { { 0, 0 } }, gr_complex(0, 0)); }, "pilot_symbol");
        frame_settings fs;
        assert_error([&] { pilot_mask::uniform(16, 64, 8).check_frame(fs, "pilot_extractor"); },
                     "pilot_extractor: the pilot mask is 16 x 64 but the frame is 32 x 64 "
                     "(n_symbols: the mask has 16, the frame has 32)");
        // Both fields differ: each is named with both values.
        assert_error([&] { pilot_mask::uniform(16, 128, 8).check_frame(fs, "frame_sync"); },
                     "frame_sync: the pilot mask is 16 x 128 but the frame is 32 x 64 (n_symbols: the mask has 16, "
                     "the frame has 32; n_subcarriers: the mask has 128, the frame has 64)");
    }

    void power_round_trip()
    {
        // Positions out of mask order: each energy follows its pilot into mask order.
        const std::vector<double> power{ 0.5, 2.0, 1.25, 0.25 };
        pilot_mask mk(4, 8, { { 2, 3 }, { 0, 5 }, { 1, 1 }, { 0, 2 } }, gr_complex(0.0f, 1.0f),
                      { { "kind", "explicit" } }, "powered", power);
        CPPUNIT_ASSERT(!mk.equal_power());
        const std::vector<double> in_order{ 0.25, 2.0, 1.25, 0.5 }; // (0,2) (0,5) (1,1) (2,3)
        CPPUNIT_ASSERT(mk.power() == in_order);
        for (int k = 0; k < mk.size(); ++k) {
            const double p = in_order[k];
            CPPUNIT_ASSERT_DOUBLES_EQUAL(1.0 / std::sqrt(p), mk.noise_scale(k), 1e-15);
            const gr_complex x = mk.transmitted_pilot(k);
            CPPUNIT_ASSERT_DOUBLES_EQUAL(0.0, x.real(), 1e-7);
            CPPUNIT_ASSERT_DOUBLES_EQUAL(std::sqrt(p), x.imag(), 1e-6);
        }
        check_lists(mk); // the allocator's lists carry the energies
        const auto back = through_file(mk, "qa_pilot_mask_power.json");
        CPPUNIT_ASSERT(back == mk);
        CPPUNIT_ASSERT(back.power() == in_order);
        CPPUNIT_ASSERT(mk.to_json().contains("power"));
        // A file's power[i] belongs to pilots[i] as listed.
        const auto listed = pilot_mask::parse(mask_text("[[3, 0], [0, 0]]", 4, 8, R"(, "power": [1.5, 0.5])"), "l.json");
        CPPUNIT_ASSERT((listed.power() == std::vector<double>{ 0.5, 1.5 }));

        // Without `power`: equal power, written as before, and the same mask as before.
        const auto plain = pilot_mask::parse(mask_text("[[0, 1], [2, 3]]"), "plain.json");
        CPPUNIT_ASSERT(plain.equal_power());
        CPPUNIT_ASSERT((plain.power() == std::vector<double>{ 1.0, 1.0 }));
        CPPUNIT_ASSERT(!plain.to_json().contains("power"));
        CPPUNIT_ASSERT_EQUAL(1.0, plain.noise_scale(1));
        CPPUNIT_ASSERT(plain.transmitted_pilot(0) == plain.pilot_symbol());
        // An explicit list of ones is equal power, and equal to the mask without it.
        const auto ones = pilot_mask::parse(mask_text("[[0, 1], [2, 3]]", 4, 8, R"(, "power": [1, 1])"), "ones.json");
        CPPUNIT_ASSERT(ones.equal_power() && ones == plain);
        // Unequal energies are a different mask.
        const auto other = pilot_mask::parse(mask_text("[[0, 1], [2, 3]]", 4, 8, R"(, "power": [0.5, 1.5])"), "o.json");
        CPPUNIT_ASSERT(!(other == plain));
        // The mean may be off by rounding (relative 1e-6), not more.
        pilot_mask(2, 2, { { 0, 0 }, { 1, 1 } }, { 1.0f, 0.0f }, { { "kind", "explicit" } }, "tol",
                   { 0.5 + 5e-7, 1.5 + 5e-7 });
    }

    void bad_power_is_refused()
    {
        auto with = [](const std::string& power) {
            return mask_text("[[0, 1], [2, 3], [3, 7]]", 4, 8, R"(, "power": )" + power);
        };
        assert_error([&] { pilot_mask::parse(with("[1, 1]"), "short.json"); },
                     "short.json: power: lists 2 energies for 3 pilots");
        assert_error([&] { pilot_mask::parse(with("[1, 1, 1, 0]"), "long.json"); },
                     "long.json: power: lists 4 energies for 3 pilots");
        assert_error([&] { pilot_mask::parse(with("[2, -0.5, 1.5]"), "neg.json"); },
                     "neg.json: power[1]: must not be negative");
        assert_error([&] { pilot_mask::parse(with("[1.5, 1.5, 0]"), "zero.json"); },
                     "zero.json: power[2]: is 0", "energy > 0");
        assert_error([&] { pilot_mask::parse(with("[0, 0, 0]"), "allzero.json"); },
                     "allzero.json: power: every pilot has zero energy");
        assert_error([&] { pilot_mask::parse(with("[1, 1, 1.1]"), "mean.json"); },
                     "mean.json: power: the mean is 1.033333", "must be 1");
        assert_error([&] { pilot_mask::parse(with("[1, 1, 1.00001]"), "mean2.json"); }, "mean2.json: power: the mean");
        assert_error([&] { pilot_mask::parse(with("[1, null, 1]"), "null.json"); }, "null.json: power[1]");
        assert_error([&] { pilot_mask::parse(with("[1, \"a\", 1]"), "str.json"); }, "str.json: power[1]");
        assert_error([&] { pilot_mask::parse(with("1"), "scalar.json"); }, "scalar.json: power: expected a list");
        const double inf = std::numeric_limits<double>::infinity();
        for (double bad : { inf, -inf, std::nan("") })
            assert_error([&] { pilot_mask(2, 2, { { 0, 0 }, { 1, 1 } }, { 1.0f, 0.0f }, { { "kind", "explicit" } },
                                          "nonfinite", { bad, 1.0 }); },
                         "nonfinite: power[0]: must be finite");
        assert_error([&] { pilot_mask(2, 2, { { 0, 0 } }, { 1.0f, 0.0f }, { { "kind", "explicit" } }, "len", { 0.5, 1.5 }); },
                     "len: power: lists 2 energies for 1 pilots");
    }

    void phases_round_trip()
    {
        // Positions out of mask order: each phase follows its pilot into mask order, with its energy.
        const std::vector<double> power{ 0.5, 2.0, 1.25, 0.25 }, phases{ 0.5, -1.0, 3.0, 2.25 };
        const gr_complex sp(0.6f, -0.8f);
        pilot_mask mk(4, 8, { { 2, 3 }, { 0, 5 }, { 1, 1 }, { 0, 2 } }, sp, { { "kind", "explicit" } }, "phased",
                      power, phases);
        CPPUNIT_ASSERT(!mk.zero_phases() && mk.phase_sequence().empty());
        const std::vector<double> p_order{ 0.25, 2.0, 1.25, 0.5 }, phi_order{ 2.25, -1.0, 3.0, 0.5 };
        CPPUNIT_ASSERT(mk.power() == p_order && mk.phases() == phi_order);
        for (int k = 0; k < mk.size(); ++k) { // sqrt(p_k)·s_p·exp(jφ_k)
            const std::complex<double> want =
                std::sqrt(p_order[k]) * std::complex<double>(sp) * std::polar(1.0, phi_order[k]);
            CPPUNIT_ASSERT_DOUBLES_EQUAL(want.real(), mk.transmitted_pilot(k).real(), 1e-6);
            CPPUNIT_ASSERT_DOUBLES_EQUAL(want.imag(), mk.transmitted_pilot(k).imag(), 1e-6);
            CPPUNIT_ASSERT_DOUBLES_EQUAL(1.0 / std::sqrt(p_order[k]), mk.noise_scale(k), 1e-15);
        }
        check_lists(mk); // and the phases
        const auto back = through_file(mk, "qa_pilot_mask_phases.json");
        CPPUNIT_ASSERT(back == mk && back.phases() == phi_order);
        for (int k = 0; k < mk.size(); ++k)
            CPPUNIT_ASSERT(back.transmitted_pilot(k) == mk.transmitted_pilot(k));
        // A file's phases[i] belongs to pilots[i] as listed.
        const auto listed =
            pilot_mask::parse(mask_text("[[3, 0], [0, 0]]", 4, 8, R"(, "phases": [1.5, -0.5])"), "l.json");
        CPPUNIT_ASSERT((listed.phases() == std::vector<double>{ -0.5, 1.5 }));

        // A named sequence is written by name and read back to the same phases.
        const auto newman = pilot_mask::parse(
            mask_text("[[1, 6], [0, 2], [1, 0], [0, 7], [1, 3], [0, 4]]", 4, 8, R"(, "phases": "newman")"), "n.json");
        CPPUNIT_ASSERT_EQUAL(std::string("newman"), newman.phase_sequence());
        CPPUNIT_ASSERT_EQUAL(std::string("newman"), newman.to_json().at("phases").get<std::string>());
        // Per symbol, in subcarrier order: π·i²/K with K = 3 on symbols 0 and 1.
        const std::vector<double> row{ 0.0, M_PI / 3.0, 4.0 * M_PI / 3.0 };
        CPPUNIT_ASSERT(pilot_mask::newman_phases(3) == row);
        for (int k = 0; k < 6; ++k)
            CPPUNIT_ASSERT_EQUAL(row[k % 3], newman.phases()[k]);
        CPPUNIT_ASSERT(pilot_mask::parse(newman.to_json_string(), "again") == newman);
        const auto plain = pilot_mask::parse(mask_text("[[1, 6], [0, 2], [1, 0], [0, 7], [1, 3], [0, 4]]"), "p.json");
        CPPUNIT_ASSERT(plain.with_phases("newman") == newman);
        CPPUNIT_ASSERT(newman.with_phases(newman.phases()) == newman); // the same phases as a list
        CPPUNIT_ASSERT(newman.with_phases(newman.phases()).to_json().at("phases").is_array());

        // Without `phases`: all 0, written as before, the transmitted values bit for bit s_p.
        CPPUNIT_ASSERT(plain.zero_phases() && plain.phase_sequence().empty());
        CPPUNIT_ASSERT(!plain.to_json().contains("phases"));
        for (int k = 0; k < plain.size(); ++k)
            CPPUNIT_ASSERT(plain.transmitted_pilot(k) == plain.pilot_symbol());
        CPPUNIT_ASSERT(!(plain == newman));
        CPPUNIT_ASSERT(newman.with_phases("zero") == plain);
        CPPUNIT_ASSERT(!newman.with_phases("zero").to_json().contains("phases"));
        // An explicit list of zeros is no phases, written without the key.
        const auto zeros = pilot_mask::parse(mask_text("[[0, 1], [2, 3]]", 4, 8, R"(, "phases": [0, 0])"), "z.json");
        CPPUNIT_ASSERT(zeros.zero_phases() && zeros == pilot_mask::parse(mask_text("[[0, 1], [2, 3]]"), "p2.json"));
        CPPUNIT_ASSERT(!zeros.to_json().contains("phases"));
        // Energies without phases: the same bits as sqrt(p)·s_p before phases existed.
        const pilot_mask powered(4, 8, { { 0, 1 }, { 2, 3 } }, sp, { { "kind", "explicit" } }, "pw", { 0.5, 1.5 });
        CPPUNIT_ASSERT(powered.transmitted_pilot(0) == sp * static_cast<float>(std::sqrt(0.5)));
        CPPUNIT_ASSERT(powered.transmitted_pilot(1) == sp * static_cast<float>(std::sqrt(1.5)));
    }

    void newman_crest_factor()
    {
        // K pilots of equal phase on one symbol add up at t = 0: peak K, rms sqrt(K) (Parseval),
        // so the crest factor is sqrt(K) exactly, between the samples too.
        const auto shipped = one_symbol(32, 64, 32, 1, 16);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(std::sqrt(32.0), crest_factor(shipped, 16, 1), 1e-9);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(std::sqrt(32.0), crest_factor(shipped, 16, 8), 1e-9);
        // Newman phases on all M = 64 subcarriers (even M): a Zadoff–Chu sequence of root 1,
        // whose M-point transform has constant modulus: crest factor 1 at the samples.
        std::vector<pilot_position> all;
        for (int m = 0; m < 64; ++m)
            all.push_back({ 0, m });
        const auto full = pilot_mask(1, 64, all).with_phases("newman");
        CPPUNIT_ASSERT_DOUBLES_EQUAL(1.0, crest_factor(full, 0, 1), 1e-6); // the pilots are floats
        CPPUNIT_ASSERT_DOUBLES_EQUAL(1.0, crest_factor(pilot_mask(1, 64, all), 0, 1) / 8.0, 1e-9); // sqrt(64) without
        // On the shipped delay mask's 32 random subcarriers (pilot_mask.h states these values):
        // 2.23 at the 64 samples, 2.68 between them (the peak 16x oversampled), against 5.66.
        const auto phased = shipped.with_phases("newman");
        CPPUNIT_ASSERT_DOUBLES_EQUAL(2.23, crest_factor(phased, 16, 1), 0.005);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(2.68, crest_factor(phased, 16, 16), 0.01);
        // The energies are untouched: the symbol's rms is the same with and without phases.
        double e0 = 0.0, e1 = 0.0;
        for (int k = 0; k < shipped.size(); ++k) {
            e0 += std::norm(shipped.transmitted_pilot(k));
            e1 += std::norm(phased.transmitted_pilot(k));
        }
        CPPUNIT_ASSERT_DOUBLES_EQUAL(e0, e1, 1e-5);
    }

    void bad_phases_are_refused()
    {
        // Each file's "phases" value for three pilots, and the words its error must contain.
        const std::vector<std::pair<std::string, std::string>> files{
            { "[1, 1]", "phases: lists 2 phases for 3 pilots" },
            { "[1, 1, 1, 0]", "phases: lists 4 phases for 3 pilots" },
            { "[1, null, 1]", "phases[1]: expected a number" },
            { "[1, \"a\", 1]", "phases[1]: expected a number" },
            { "[]", "phases: expected a sequence name" },
            { "\"\"", "phases: expected a sequence name" },
            { "1.5", "phases: expected a sequence name" },
            { "\"schroeder\"", "phases: unknown phase sequence \"schroeder\" (known: newman" },
        };
        for (size_t i = 0; i < files.size(); ++i) {
            const std::string name = "bad" + std::to_string(i) + ".json";
            const std::string text =
                mask_text("[[0, 1], [2, 3], [3, 7]]", 4, 8, R"(, "phases": )" + files[i].first);
            assert_error([&] { pilot_mask::parse(text, name); }, name + ": " + files[i].second);
        }
        const double inf = std::numeric_limits<double>::infinity();
        for (double bad : { inf, -inf, std::nan("") })
            assert_error([&] { pilot_mask(2, 2, { { 0, 0 }, { 1, 1 } }, { 1.0f, 0.0f }, { { "kind", "explicit" } },
                                          "nonfinite", {}, { 0.0, bad }); },
                         "nonfinite: phases[1]: must be a finite number");
        assert_error([&] { pilot_mask(2, 2, { { 0, 0 } }, { 1.0f, 0.0f }, { { "kind", "explicit" } }, "both", {},
                                      { 0.5 }, "newman"); },
                     "both: phases: give a list of phases or a sequence name, not both");
        const auto mk = pilot_mask::uniform(4, 8, 3);
        assert_error([&] { mk.with_phases(std::vector<double>{ 0.1, 0.2 }, "caller"); },
                     "caller: phases: lists 2 phases for 3 pilots");
        assert_error([&] { mk.with_phases(std::vector<double>{}, "caller"); }, "caller: phases: lists 0 phases");
        assert_error([&] { mk.with_phases(std::string("chirp"), "caller"); }, "caller: phases: unknown phase sequence");
        assert_error([&] { mk.with_phases(std::string(), "caller"); }, "caller: phases: no sequence named");
        assert_error([] { pilot_mask::newman_phases(0); }, "newman_phases: count must be >= 1");
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_pilot_mask);
