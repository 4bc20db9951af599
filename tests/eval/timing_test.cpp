#include "asynevo/eval/timing.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "asynevo/core/error.hpp"

namespace asynevo::eval {
namespace {

namespace fs = std::filesystem;

class Timing : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / (std::string("asynevo_timing_") + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& content) {
    const std::string path = (dir_ / "timing.csv").string();
    std::ofstream(path) << content;
    return path;
  }
  fs::path dir_;
};

TEST_F(Timing, PerStageStatisticsAndRealTimeFactor) {
  // 5 updates over 2 s of event time; total 1+2+3+4+10 = 20 ms -> real-time factor 0.01.
  const TimingStats s =
      readTimingStats(write("t_s, window_size, solve_ms, total_ms\n"
                            "1.0, 10, 0.5, 1\n"
                            "1.5, 12, 1.5, 2\n"
                            "# a comment\n"
                            "2.0, 14, 2.5, 3\n"
                            "2.5, 16, 3.5, 4\n"
                            "3.0, 18, 9.5, 10\n"));
  EXPECT_EQ(s.updates, 5u);
  EXPECT_DOUBLE_EQ(s.t_first_s, 1.0);
  EXPECT_DOUBLE_EQ(s.t_last_s, 3.0);
  ASSERT_EQ(s.stages.size(), 2u);
  EXPECT_EQ(s.stages[0].name, "solve_ms");
  const ColumnStats& total = s.stages[1];
  EXPECT_EQ(total.name, "total_ms");
  EXPECT_DOUBLE_EQ(total.mean, 4.0);
  EXPECT_DOUBLE_EQ(total.median, 3.0);
  EXPECT_DOUBLE_EQ(total.p95, 4.0 + 0.8 * 6.0);  // rank 0.95·4 = 3.8 between 4 and 10
  EXPECT_DOUBLE_EQ(total.max, 10.0);
  EXPECT_DOUBLE_EQ(total.sum, 20.0);
  EXPECT_TRUE(s.has_total);
  EXPECT_DOUBLE_EQ(s.backend_real_time_factor, 0.02 / 2.0);
  ASSERT_EQ(s.others.size(), 1u);
  EXPECT_EQ(s.others[0].name, "window_size");
  EXPECT_DOUBLE_EQ(s.others[0].mean, 14.0);
}

TEST_F(Timing, WithoutTotalThereIsNoRealTimeFactor) {
  const TimingStats s = readTimingStats(write("t,a_ms\n0,1\n1,2\n"));
  EXPECT_FALSE(s.has_total);
  EXPECT_EQ(s.backend_real_time_factor, 0.0);
}

TEST_F(Timing, BadFilesNameTheLine) {
  EXPECT_THROW(readTimingStats((dir_ / "missing.csv").string()), InputError);
  EXPECT_THROW(readTimingStats(write("")), InputError);
  EXPECT_THROW(readTimingStats(write("t,total_ms\n")), InputError);  // no rows
  try {
    readTimingStats(write("t,total_ms\n0,1\n1,abc\n"));
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(e.location(), 3u);
    EXPECT_NE(e.message().find("total_ms 'abc'"), std::string::npos) << e.what();
  }
  try {
    readTimingStats(write("t,total_ms\n0,1,2\n"));
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(e.location(), 2u);
  }
}

}  // namespace
}  // namespace asynevo::eval
