// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief An RBF support-vector classifier on feature vectors (libsvm), with the
 *        z-score standardisation learned from the training set.
 *
 * \details Used by the feature-SVM
 * recognition baseline (doppler_features → feature_svm).
 */
#ifndef INCLUDED_SEMS_BASELINES_FEATURE_SVM_H
#define INCLUDED_SEMS_BASELINES_FEATURE_SVM_H

#include <gnuradio/sems/baselines/api.h>
#include <memory>
#include <vector>

namespace gr {
namespace sems {

/*! \brief An RBF support-vector classifier on standardised feature vectors (libsvm). */
class SEMS_BASELINES_API feature_svm
{
public:
    /*! \brief Training settings. */
    struct settings {
        double c = 10.0;     ///< soft-margin cost C, > 0
        double gamma = -1.0; ///< RBF width; <= 0 means 1 / n_features (on standardised features)
        double cache_mb = 100.0; ///< libsvm kernel cache in MB
    };

    /*!
     * \brief Trains the classifier.
     * \param features n_samples rows of equal length, finite.
     * \param labels one per row, >= 0, at least two classes.
     * \param s the settings.
     * \throws std::invalid_argument naming the problem.
     */
    feature_svm(const std::vector<std::vector<double>>& features, const std::vector<int>& labels, settings s);
    /*!
     * \brief Trains the classifier with default settings.
     * \param features n_samples rows of equal length, finite.
     * \param labels one per row, >= 0, at least two classes.
     * \throws std::invalid_argument naming the problem.
     */
    feature_svm(const std::vector<std::vector<double>>& features, const std::vector<int>& labels);
    ~feature_svm(); ///< Destructor.
    /*! \brief Move constructor. */
    feature_svm(feature_svm&&) noexcept;

    /*!
     * \brief Classifies one feature vector.
     * \param x n_features() values.
     * \return the predicted label.
     * \throws std::invalid_argument on a wrong length or non-finite values.
     */
    int predict(const std::vector<double>& x) const;
    /*! \brief The feature length. \return the values per feature vector. */
    int n_features() const;
    /*! \brief The model size. \return the number of support vectors. */
    int n_support_vectors() const;

private:
    struct impl;
    std::unique_ptr<impl> d_impl;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_BASELINES_FEATURE_SVM_H */
