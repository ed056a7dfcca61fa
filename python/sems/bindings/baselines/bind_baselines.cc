// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: Python bindings of the classical baselines (delay estimators, CRB,
 * Doppler features, feature SVM, MUSIC pilot patterns, angle estimators, the MIMO mask's
 * azimuth bound and estimator). Observations are 1-D complex64 numpy arrays of length N_p
 * in mask order (a MIMO mask's: N_r·N_p, receive-element-major as mimo_pilots gives them). */
#include <gnuradio/sems/baselines/angle_estimators.h>
#include <gnuradio/sems/baselines/array_beamformer.h>
#include <gnuradio/sems/baselines/subcarrier_masks.h>
#include <gnuradio/sems/baselines/music_delay_estimator.h>
#include <gnuradio/sems/baselines/omp_delay_estimator.h>
#include <gnuradio/sems/baselines/periodogram_delay_estimator.h>
#include <gnuradio/sems/baselines/delay_crb.h>
#include <gnuradio/sems/baselines/delay_search.h>
#include <gnuradio/sems/baselines/doppler_features.h>
#include <gnuradio/sems/baselines/feature_svm.h>
#include <gnuradio/sems/baselines/mimo_angle.h>

#include "sems_pydoc.h" // D(...): docstrings from the headers' Doxygen (docs/doxygen_pydoc.py)
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <stdexcept>
#include <string>

namespace py = pybind11;
using namespace gr::sems;

namespace {

using carray = py::array_t<gr_complex, py::array::c_style | py::array::forcecast>;

// An array's observations: K x L (elements x snapshots), element-major as the extractor gives them.
std::pair<const gr_complex*, int> array_obs(const carray& a, int elements, const char* who)
{
    if (a.ndim() != 2 || a.shape(0) != elements)
        throw std::invalid_argument(std::string(who) + ": expected a 2-D array of " + std::to_string(elements) +
                                    " elements x snapshots, got " + std::to_string(a.ndim()) + "-D with first size " +
                                    std::to_string(a.ndim() > 0 ? a.shape(0) : 0));
    return { a.data(), static_cast<int>(a.shape(1)) };
}

const gr_complex* obs_ptr(const carray& a, int n_pilots, const char* who)
{
    if (a.ndim() != 1 || a.shape(0) != n_pilots)
        throw std::invalid_argument(std::string(who) + ": expected a 1-D array of " + std::to_string(n_pilots) +
                                    " observations");
    return a.data();
}

// mimo_ml_angle_estimator with the length of its observations (N_r·N_p), which the class does
// not expose: estimate() and likelihood() read that many values from the pointer they get.
struct mimo_ml_checked {
    mimo_ml_angle_estimator estimator;
    int n_receive;
    int n_pilots;
};

const gr_complex* mimo_obs_ptr(const mimo_ml_checked& e, const carray& a, const char* who)
{
    const py::ssize_t want = py::ssize_t(e.n_receive) * e.n_pilots;
    if (a.ndim() != 1 || a.shape(0) != want)
        throw std::invalid_argument(std::string(who) + ": expected a 1-D array of N_r·N_p = " +
                                    std::to_string(e.n_receive) + "·" + std::to_string(e.n_pilots) + " = " +
                                    std::to_string(want) +
                                    " observations (receive-element-major, as mimo_pilots gives them), got a " +
                                    std::to_string(a.ndim()) + "-D array of " + std::to_string(a.size()) + " values");
    return a.data();
}

} // namespace

void bind_baselines(py::module& m)
{
    py::class_<delay_search>(m, "delay_search", D(delay_search))
        .def(py::init([](int oversample, double min_index, double max_index) {
                 return delay_search{ oversample, min_index, max_index };
             }),
             py::arg("oversample") = 8, py::arg("min_index") = 0.0, py::arg("max_index") = -1.0)
        .def_readwrite("oversample", &delay_search::oversample)
        .def_readwrite("min_index", &delay_search::min_index)
        .def_readwrite("max_index", &delay_search::max_index)
        .def("grid", &delay_search::grid);

    py::enum_<slow_time_model>(m, "slow_time_model", D(slow_time_model))
        .value("joint_doppler", slow_time_model::joint_doppler)
        .value("per_symbol", slow_time_model::per_symbol);

    py::class_<periodogram_delay_estimator>(m, "periodogram_delay_estimator", D(periodogram_delay_estimator))
        .def(py::init([](const frame_settings& fs, const pilot_mask& mask, const delay_search& search,
                         int doppler_oversample, slow_time_model slow, bool refine) {
                 return new periodogram_delay_estimator(fs, mask, { search, doppler_oversample, slow, refine });
             }),
             py::arg("fs"), py::arg("mask"), py::arg("search") = delay_search{}, py::arg("doppler_oversample") = 2,
             py::arg("slow_time") = slow_time_model::joint_doppler, py::arg("refine") = true)
        .def("estimate_index",
             [](const periodogram_delay_estimator& e, const carray& obs) {
                 return e.estimate_index(obs_ptr(obs, e.n_pilots(), "estimate_index"));
             })
        .def("profile",
             [](const periodogram_delay_estimator& e, const carray& obs) {
                 return e.profile(obs_ptr(obs, e.n_pilots(), "profile"));
             })
        .def("grid_index", &periodogram_delay_estimator::grid_index)
        .def("n_pilots", &periodogram_delay_estimator::n_pilots);

    py::class_<omp_delay_estimator>(m, "omp_delay_estimator", D(omp_delay_estimator))
        .def(py::init([](const frame_settings& fs, const pilot_mask& mask, const delay_search& search,
                         int doppler_oversample, int n_atoms, double relative_power) {
                 return new omp_delay_estimator(fs, mask, { search, doppler_oversample, n_atoms, relative_power });
             }),
             py::arg("fs"), py::arg("mask"), py::arg("search") = delay_search{}, py::arg("doppler_oversample") = 2,
             py::arg("n_atoms") = 1, py::arg("relative_power") = 0.25)
        .def("estimate_index",
             [](const omp_delay_estimator& e, const carray& obs) {
                 return e.estimate_index(obs_ptr(obs, e.n_pilots(), "estimate_index"));
             })
        .def("n_pilots", &omp_delay_estimator::n_pilots);

    py::class_<music_delay_estimator>(m, "music_delay_estimator", D(music_delay_estimator))
        .def(py::init([](const frame_settings& fs, const pilot_mask& mask, const delay_search& search, int n_paths) {
                 return new music_delay_estimator(fs, mask, { search, n_paths });
             }),
             py::arg("fs"), py::arg("mask"), py::arg("search") = delay_search{}, py::arg("n_paths") = 1)
        .def("estimate_index",
             [](const music_delay_estimator& e, const carray& obs) {
                 return e.estimate_index(obs_ptr(obs, e.n_pilots(), "estimate_index"));
             })
        .def("pseudo_spectrum",
             [](const music_delay_estimator& e, const carray& obs) {
                 return e.pseudo_spectrum(obs_ptr(obs, e.n_pilots(), "pseudo_spectrum"));
             })
        .def("grid_index", &music_delay_estimator::grid_index)
        .def("coarray_spacing", &music_delay_estimator::coarray_spacing)
        .def("coarray_length", &music_delay_estimator::coarray_length)
        .def("n_pilots", &music_delay_estimator::n_pilots);

    py::class_<delay_crb>(m, "delay_crb", D(delay_crb))
        .def_static("variance_index", &delay_crb::variance_index, py::arg("fs"), py::arg("mask"), py::arg("snr_db"),
                    py::arg("doppler_known") = false, py::arg("gain_power") = 1.0)
        .def_static("mae_index", &delay_crb::mae_index, py::arg("fs"), py::arg("mask"), py::arg("snr_db"),
                    py::arg("doppler_known") = false, py::arg("rayleigh") = true, py::arg("mean_power") = 1.0)
        .def_static("spread", &delay_crb::spread, py::arg("mask"), py::arg("doppler_known"));

    py::class_<doppler_features>(m, "doppler_features", D(doppler_features))
        .def(py::init<const frame_settings&, const pilot_mask&, int>(), py::arg("fs"), py::arg("mask"),
             py::arg("oversample") = 1)
        .def_static("names", &doppler_features::names)
        .def("frequencies_hz", &doppler_features::frequencies_hz)
        .def("spectrum",
             [](const doppler_features& f, const carray& obs) {
                 return f.spectrum(obs_ptr(obs, f.n_pilots(), "spectrum"));
             })
        .def("extract", [](const doppler_features& f, const carray& obs) {
            return f.extract(obs_ptr(obs, f.n_pilots(), "extract"));
        });

    py::class_<feature_svm>(m, "feature_svm", D(feature_svm))
        .def(py::init([](const std::vector<std::vector<double>>& x, const std::vector<int>& y, double c, double gamma) {
                 return new feature_svm(x, y, { c, gamma, 100.0 });
             }),
             py::arg("features"), py::arg("labels"), py::arg("c") = 10.0, py::arg("gamma") = -1.0)
        .def("predict", &feature_svm::predict)
        .def("n_features", &feature_svm::n_features)
        .def("n_support_vectors", &feature_svm::n_support_vectors);

    py::class_<angle_search>(m, "angle_search", D(angle_search))
        .def(py::init([](double min_rad, double max_rad, int grid) { return angle_search{ min_rad, max_rad, grid }; }),
             py::arg("min_rad") = angle_search{}.min_rad, py::arg("max_rad") = angle_search{}.max_rad,
             py::arg("grid") = angle_search{}.grid)
        .def_readwrite("min_rad", &angle_search::min_rad)
        .def_readwrite("max_rad", &angle_search::max_rad)
        .def_readwrite("grid", &angle_search::grid);
    m.def("angle_crb_rad2", &angle_crb_rad2, D(angle_crb_rad2), py::arg("array"), py::arg("azimuth_rad"),
          py::arg("elevation_rad"), py::arg("wavelength_m"), py::arg("energy_to_noise"));
    py::class_<beamforming_angle_estimator>(m, "beamforming_angle_estimator", D(beamforming_angle_estimator))
        .def(py::init<const array_geometry&, double, double, angle_search>(), py::arg("array"),
             py::arg("elevation_rad"), py::arg("wavelength_m"), py::arg("search") = angle_search{})
        .def("estimate",
             [](const beamforming_angle_estimator& e, const carray& y, int n_targets) {
                 const auto [p, l] = array_obs(y, e.n_elements(), "estimate");
                 return e.estimate(p, l, n_targets);
             },
             D(beamforming_angle_estimator, estimate), py::arg("y"), py::arg("n_targets") = 1)
        .def("spectrum",
             [](const beamforming_angle_estimator& e, const carray& y) {
                 const auto [p, l] = array_obs(y, e.n_elements(), "spectrum");
                 return e.spectrum(p, l);
             },
             D(beamforming_angle_estimator, spectrum), py::arg("y"));
    m.def(
        "beamform_pilots",
        [](const array_geometry& a, double azimuth_rad, double elevation_rad, double wavelength_m, const carray& y) {
            const auto [p, l] = array_obs(y, a.n_receive() * a.n_transmit(), "beamform_pilots");
            py::array_t<gr_complex> z(l);
            beamform_pilots(a, azimuth_rad, elevation_rad, wavelength_m, p, l, z.mutable_data());
            return z;
        },
        D(beamform_pilots), py::arg("array"), py::arg("azimuth_rad"), py::arg("elevation_rad"), py::arg("wavelength_m"),
        py::arg("y"));
    py::class_<array_beamformer>(m, "array_beamformer", D(array_beamformer))
        .def(py::init<const array_geometry&, double>(), py::arg("array"), py::arg("wavelength_m"))
        .def("n_elements", &array_beamformer::n_elements, D(array_beamformer, n_elements))
        .def(
            "combine",
            [](const array_beamformer& b, const carray& y) {
                const auto [p, l] = array_obs(y, b.n_elements(), "combine");
                py::array_t<gr_complex> z(l);
                const double azimuth = b.combine(p, l, z.mutable_data());
                return py::make_tuple(azimuth, z);
            },
            D(array_beamformer, combine), py::arg("y"));
    py::class_<capon_angle_estimator>(m, "capon_angle_estimator", D(capon_angle_estimator))
        .def(py::init<const array_geometry&, double, double, double, int, angle_search>(), py::arg("array"),
             py::arg("elevation_rad"), py::arg("wavelength_m"), py::arg("loading") = 1e-3, py::arg("subarray") = 0,
             py::arg("search") = angle_search{})
        .def("estimate",
             [](const capon_angle_estimator& e, const carray& y, int n_targets) {
                 const auto [p, l] = array_obs(y, e.n_elements(), "estimate");
                 return e.estimate(p, l, n_targets);
             },
             D(capon_angle_estimator, estimate), py::arg("y"), py::arg("n_targets") = 1);
    py::class_<music_angle_estimator>(m, "music_angle_estimator", D(music_angle_estimator))
        .def(py::init<const array_geometry&, double, double, int, int, angle_search>(), py::arg("array"),
             py::arg("elevation_rad"), py::arg("wavelength_m"), py::arg("n_targets"), py::arg("subarray") = 0,
             py::arg("search") = angle_search{})
        .def("estimate",
             [](const music_angle_estimator& e, const carray& y) {
                 const auto [p, l] = array_obs(y, e.n_elements(), "estimate");
                 return e.estimate(p, l);
             },
             D(music_angle_estimator, estimate), py::arg("y"));

    m.def("mimo_angle_crb_rad2", &mimo_angle_crb_rad2, D(mimo_angle_crb_rad2), py::arg("array"), py::arg("mask"),
          py::arg("fs"), py::arg("azimuth_rad"), py::arg("elevation_rad"), py::arg("snr"));
    py::class_<mimo_ml_estimate>(m, "mimo_ml_estimate", D(mimo_ml_estimate))
        .def_readonly("azimuth_rad", &mimo_ml_estimate::azimuth_rad, D(mimo_ml_estimate, azimuth_rad))
        .def_readonly("delay_index", &mimo_ml_estimate::delay_index, D(mimo_ml_estimate, delay_index))
        .def_readonly("doppler_bins", &mimo_ml_estimate::doppler_bins, D(mimo_ml_estimate, doppler_bins));
    py::class_<mimo_ml_checked>(m, "mimo_ml_angle_estimator", D(mimo_ml_angle_estimator))
        .def(py::init([](const array_geometry& a, const mimo_mask& mk, const frame_settings& fs, double elevation_rad,
                         angle_search search, int oversample) {
                 return mimo_ml_checked{ mimo_ml_angle_estimator(a, mk, fs, elevation_rad, search, oversample),
                                         a.n_receive(), mk.mask().size() };
             }),
             D(mimo_ml_angle_estimator, mimo_ml_angle_estimator), py::arg("array"), py::arg("mask"), py::arg("fs"),
             py::arg("elevation_rad"), py::arg("search") = angle_search{}, py::arg("oversample") = 2)
        .def(
            "estimate",
            [](const mimo_ml_checked& e, const carray& y) {
                const gr_complex* p = mimo_obs_ptr(e, y, "mimo_ml_angle_estimator.estimate");
                py::gil_scoped_release nogil;
                return e.estimator.estimate(p);
            },
            D(mimo_ml_angle_estimator, estimate), py::arg("y"))
        .def(
            "likelihood",
            [](const mimo_ml_checked& e, const carray& y, double azimuth_rad, double delay_index, double doppler_bins) {
                return e.estimator.likelihood(mimo_obs_ptr(e, y, "mimo_ml_angle_estimator.likelihood"), azimuth_rad,
                                              delay_index, doppler_bins);
            },
            D(mimo_ml_angle_estimator, likelihood), py::arg("y"), py::arg("azimuth_rad"), py::arg("delay_index"),
            py::arg("doppler_bins"));

    m.def("random_subcarrier_mask", &random_subcarrier_mask, D(random_subcarrier_mask), py::arg("n_symbols"), py::arg("n_subcarriers"),
          py::arg("count"), py::arg("seed"), "RP-MUSIC pattern: the uniform lattice's symbols, random subcarriers");
    m.def("nested_subcarrier_mask", &nested_subcarrier_mask, D(nested_subcarrier_mask), py::arg("n_symbols"), py::arg("n_subcarriers"),
          py::arg("count"), py::arg("rows") = 2, "OP-MUSIC pattern: nested-array subcarriers on a few symbols");
}
