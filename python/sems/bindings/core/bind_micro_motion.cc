// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: Python bindings of the micro-motion models (micro_motion.h) and the class
 * libraries (class_library.h). A micro_motion is a std::variant: Python passes and gets one
 * of rotor_motion, walker_motion, wheels_motion, scatterers_motion (pybind11/stl.h). JSON
 * crosses the boundary as text, as elsewhere in the bindings.
 */
#include <gnuradio/sems/core/scene/class_library.h>
#include <gnuradio/sems/core/scene/micro_motion.h>

#include "sems_pydoc.h" // D(...): docstrings from the headers' Doxygen (docs/doxygen_pydoc.py)
#include <pybind11/operators.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

namespace py = pybind11;
using namespace gr::sems;

namespace {

// pybind11 holds libraries as shared_ptr<class_library>; the library API hands out const ones.
std::shared_ptr<class_library> mutable_ptr(std::shared_ptr<const class_library> p)
{
    return std::const_pointer_cast<class_library>(std::move(p));
}

template <typename T>
std::string repr_of(const T& m)
{
    return micro_motion_to_json(micro_motion{ m }).dump();
}

} // namespace

void bind_micro_motion(py::module& m)
{
    py::class_<rotor_motion>(m, "rotor_motion", D(rotor_motion))
        .def(py::init([](int rotors, int blades, double blade_length_m, std::vector<double> rotation_hz,
                         std::vector<double> phase_rad, double elevation_rad, double body_power) {
                 return rotor_motion{ rotors, blades, blade_length_m, rotation_hz, phase_rad, elevation_rad,
                                      body_power };
             }),
             py::arg("rotors") = rotor_motion{}.rotors, py::arg("blades") = rotor_motion{}.blades,
             py::arg("blade_length_m") = rotor_motion{}.blade_length_m,
             py::arg("rotation_hz") = rotor_motion{}.rotation_hz, py::arg("phase_rad") = rotor_motion{}.phase_rad,
             py::arg("elevation_rad") = rotor_motion{}.elevation_rad,
             py::arg("body_power") = rotor_motion{}.body_power)
        .def_readwrite("rotors", &rotor_motion::rotors, D(rotor_motion, rotors))
        .def_readwrite("blades", &rotor_motion::blades, D(rotor_motion, blades))
        .def_readwrite("blade_length_m", &rotor_motion::blade_length_m, D(rotor_motion, blade_length_m))
        .def_readwrite("rotation_hz", &rotor_motion::rotation_hz, D(rotor_motion, rotation_hz))
        .def_readwrite("phase_rad", &rotor_motion::phase_rad, D(rotor_motion, phase_rad))
        .def_readwrite("elevation_rad", &rotor_motion::elevation_rad, D(rotor_motion, elevation_rad))
        .def_readwrite("body_power", &rotor_motion::body_power, D(rotor_motion, body_power))
        .def(py::self == py::self)
        .def("__repr__", &repr_of<rotor_motion>);

    py::class_<walker_motion>(m, "walker_motion", D(walker_motion))
        .def(py::init([](double height_m, double phase_rad) { return walker_motion{ height_m, phase_rad }; }),
             py::arg("height_m") = walker_motion{}.height_m, py::arg("phase_rad") = walker_motion{}.phase_rad)
        .def_readwrite("height_m", &walker_motion::height_m, D(walker_motion, height_m))
        .def_readwrite("phase_rad", &walker_motion::phase_rad, D(walker_motion, phase_rad))
        .def(py::self == py::self)
        .def("__repr__", &repr_of<walker_motion>);

    const wheels_motion wd;
    py::class_<wheels_motion>(m, "wheels_motion", D(wheels_motion))
        .def(py::init([](int wheels, double wheel_radius_m, int rim_points, int spokes, double body_power,
                         double wheelbase_m, double track_m, double phase_rad) {
                 return wheels_motion{ wheels, wheel_radius_m, rim_points, spokes, body_power,
                                       wheelbase_m, track_m, phase_rad };
             }),
             py::arg("wheels") = wd.wheels, py::arg("wheel_radius_m") = wd.wheel_radius_m,
             py::arg("rim_points") = wd.rim_points, py::arg("spokes") = wd.spokes,
             py::arg("body_power") = wd.body_power, py::arg("wheelbase_m") = wd.wheelbase_m,
             py::arg("track_m") = wd.track_m, py::arg("phase_rad") = wd.phase_rad)
        .def_readwrite("wheels", &wheels_motion::wheels, D(wheels_motion, wheels))
        .def_readwrite("wheel_radius_m", &wheels_motion::wheel_radius_m, D(wheels_motion, wheel_radius_m))
        .def_readwrite("rim_points", &wheels_motion::rim_points, D(wheels_motion, rim_points))
        .def_readwrite("spokes", &wheels_motion::spokes, D(wheels_motion, spokes))
        .def_readwrite("body_power", &wheels_motion::body_power, D(wheels_motion, body_power))
        .def_readwrite("wheelbase_m", &wheels_motion::wheelbase_m, D(wheels_motion, wheelbase_m))
        .def_readwrite("track_m", &wheels_motion::track_m, D(wheels_motion, track_m))
        .def_readwrite("phase_rad", &wheels_motion::phase_rad, D(wheels_motion, phase_rad))
        .def(py::self == py::self)
        .def("__repr__", &repr_of<wheels_motion>);

    py::class_<harmonic>(m, "harmonic", D(harmonic))
        .def(py::init([](double amplitude_m, double rate_hz, double phase_rad) {
                 return harmonic{ amplitude_m, rate_hz, phase_rad };
             }),
             py::arg("amplitude_m") = 0.0, py::arg("rate_hz") = 0.0, py::arg("phase_rad") = 0.0)
        .def_readwrite("amplitude_m", &harmonic::amplitude_m, D(harmonic, amplitude_m))
        .def_readwrite("rate_hz", &harmonic::rate_hz, D(harmonic, rate_hz))
        .def_readwrite("phase_rad", &harmonic::phase_rad, D(harmonic, phase_rad));

    py::class_<point_scatterer>(m, "point_scatterer", D(point_scatterer))
        .def(py::init([](double power, std::vector<harmonic> harmonics) { return point_scatterer{ power, harmonics }; }),
             py::arg("power") = 1.0, py::arg("harmonics") = std::vector<harmonic>{})
        .def_readwrite("power", &point_scatterer::power, D(point_scatterer, power))
        .def_readwrite("harmonics", &point_scatterer::harmonics, D(point_scatterer, harmonics));

    py::class_<scatterers_motion>(m, "scatterers_motion", D(scatterers_motion))
        .def(py::init([](std::vector<point_scatterer> scatterers) { return scatterers_motion{ scatterers }; }),
             py::arg("scatterers"))
        .def_readwrite("scatterers", &scatterers_motion::scatterers, D(scatterers_motion, scatterers))
        .def(py::self == py::self)
        .def("__repr__", &repr_of<scatterers_motion>);

    m.def("micro_motion_model", &micro_motion_model, D(micro_motion_model), py::arg("m"));
    m.def(
        "micro_motion_to_json", [](const micro_motion& mm) { return micro_motion_to_json(mm).dump(); },
        D(micro_motion_to_json), py::arg("m"));
    m.def("validate_micro_motion", &validate_micro_motion, D(validate_micro_motion), py::arg("m"),
          py::arg("source") = "micro_motion", py::arg("field") = "micro_motion");
    m.def("micro_motion_extent_m", &micro_motion_extent_m, D(micro_motion_extent_m), py::arg("m"));
    m.def("micro_motion_peak_speed_mps", &micro_motion_peak_speed_mps, D(micro_motion_peak_speed_mps),
          py::arg("m"), py::arg("speed_mps"));

    py::class_<class_definition>(m, "class_definition", D(class_definition))
        .def_readonly("name", &class_definition::name, D(class_definition, name))
        .def_readonly("description", &class_definition::description, D(class_definition, description))
        .def_readonly("range_min_m", &class_definition::range_min_m, D(class_definition, range_min_m))
        .def_readonly("range_max_m", &class_definition::range_max_m, D(class_definition, range_max_m))
        .def_readonly("speed_min_mps", &class_definition::speed_min_mps, D(class_definition, speed_min_mps))
        .def_readonly("speed_max_mps", &class_definition::speed_max_mps, D(class_definition, speed_max_mps))
        .def("motion_model", &class_definition::motion_model, D(class_definition, motion_model))
        .def("max_extent_m", &class_definition::max_extent_m, D(class_definition, max_extent_m))
        .def("max_scatterer_speed_mps", &class_definition::max_scatterer_speed_mps,
             D(class_definition, max_scatterer_speed_mps))
        .def("max_sinusoid_speed_mps", &class_definition::max_sinusoid_speed_mps,
             D(class_definition, max_sinusoid_speed_mps))
        .def("__repr__", [](const class_definition& c) { return "<class_definition " + c.name + ">"; });

    py::class_<class_library, std::shared_ptr<class_library>>(m, "class_library", D(class_library))
        .def_readonly_static("format_name", &class_library::format_name, D(class_library, format_name))
        .def_readonly_static("format_version", &class_library::format_version, D(class_library, format_version))
        .def_static("paper", [] { return mutable_ptr(class_library::paper()); }, D(class_library, paper))
        .def_static(
            "find", [](const std::string& name) { return mutable_ptr(class_library::find(name)); },
            D(class_library, find), py::arg("name_or_path"))
        .def_static(
            "load", [](const std::string& path) { return mutable_ptr(class_library::load(path)); },
            D(class_library, load), py::arg("path"))
        .def_static(
            "from_json",
            [](const std::string& text, const std::string& source) {
                nlohmann::json j;
                try {
                    j = nlohmann::json::parse(text);
                } catch (const nlohmann::json::exception& e) {
                    throw std::invalid_argument(source + ": not JSON: " + e.what());
                }
                return mutable_ptr(class_library::from_json(j, source));
            },
            D(class_library, from_json), py::arg("json_text"), py::arg("source") = "class library text")
        .def(
            "to_json", [](const class_library& l) { return l.to_json().dump(); },
            D(class_library, to_json))
        .def("name", &class_library::name, D(class_library, name))
        .def("size", &class_library::size, D(class_library, size))
        .def("__len__", &class_library::size)
        .def("at", &class_library::at, D(class_library, at), py::arg("id"), py::return_value_policy::copy)
        .def("id_of", &class_library::id_of, D(class_library, id_of), py::arg("name"))
        .def("class_names", &class_library::class_names, D(class_library, class_names))
        .def("same_classes", &class_library::same_classes, D(class_library, same_classes), py::arg("other"))
        .def("difference", &class_library::difference, D(class_library, difference), py::arg("other"))
        .def("__repr__", [](const class_library& l) {
            return "<class_library " + l.name() + ": " + std::to_string(l.size()) + " classes>";
        });
}
