// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: CppUnit runner for the qa_*.cc suites of one library (lib/<library>/).
 * Usage: qa_sems_<library> [SuiteName]   (no argument: all suites)
 * Prints each test with its wall time, so the slow ones show in CTest's log.
 */
#include <cppunit/CompilerOutputter.h>
#include <cppunit/Test.h>
#include <cppunit/TestFailure.h>
#include <cppunit/TestListener.h>
#include <cppunit/TestResult.h>
#include <cppunit/TestResultCollector.h>
#include <cppunit/TestRunner.h>
#include <cppunit/extensions/TestFactoryRegistry.h>
#include <chrono>
#include <cstdio>
#include <iostream>

namespace {

// BriefTestProgressListener's "name : OK" with the test's wall time.
class timed_progress : public CppUnit::TestListener
{
public:
    void startTest(CppUnit::Test* test) override
    {
        std::cout << test->getName() << std::flush;
        failed_ = false;
        start_ = std::chrono::steady_clock::now();
    }
    void addFailure(const CppUnit::TestFailure& failure) override
    {
        std::cout << " : " << (failure.isError() ? "error" : "assertion") << std::flush;
        failed_ = true;
    }
    void endTest(CppUnit::Test*) override
    {
        const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
        char took[32];
        std::snprintf(took, sizeof took, " (%.2f s)", s);
        std::cout << (failed_ ? "" : " : OK") << took << std::endl;
    }

private:
    std::chrono::steady_clock::time_point start_;
    bool failed_ = false;
};

} // namespace

int main(int argc, char** argv)
{
    CppUnit::TestResult controller;
    CppUnit::TestResultCollector result;
    controller.addListener(&result);
    timed_progress progress;
    controller.addListener(&progress);

    CppUnit::TestRunner runner;
    runner.addTest(CppUnit::TestFactoryRegistry::getRegistry().makeTest());
    runner.run(controller, argc > 1 ? argv[1] : "");

    CppUnit::CompilerOutputter outputter(&result, std::cerr);
    outputter.write();
    const int failed = result.testFailuresTotal();
    std::cout << (result.runTests() - failed) << " passed, " << failed << " failed" << std::endl;
    return result.wasSuccessful() ? 0 : 1;
}
