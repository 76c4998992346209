// transfer.yaml's bounds: the rates' ranges and the speed caps' one checker, at and beyond their limits.

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "haptics/transfer/transfer_config.h"
#include "src/core/units.h"

namespace robossis::transfer {
namespace {

using ::testing::HasSubstr;

std::string ErrorOf(const TransferConfig& c) {
  try {
    c.Validate();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(TransferConfigTest, RatesOutsideTheirRangesAreRefusedNamingTheKey) {
  TransferConfig c;
  EXPECT_EQ(ErrorOf(c), "");  // the paper's 1 kHz and 10 kHz
  c.rates.transfer_rate_hz = kMinTransferRateHz;
  c.rates.actuation_rate_hz = kMaxActuationRateHz;
  EXPECT_EQ(ErrorOf(c), "");
  c.rates.transfer_rate_hz = c.rates.actuation_rate_hz = kMaxTransferRateHz;
  EXPECT_EQ(ErrorOf(c), "");
  for (const double hz : {0.0, 99.0, 10001.0, 1e9, std::numeric_limits<double>::quiet_NaN()}) {
    c.rates.transfer_rate_hz = hz;
    c.rates.actuation_rate_hz = 10000;
    EXPECT_THAT(ErrorOf(c), HasSubstr("'rates.transfer_rate_hz': expected a rate in [100, 10000] Hz")) << hz;
  }
  c.rates.transfer_rate_hz = 1000;
  for (const double hz : {999.0, 20001.0, 1e7, std::numeric_limits<double>::infinity()}) {
    c.rates.actuation_rate_hz = hz;
    EXPECT_THAT(ErrorOf(c), HasSubstr("'rates.actuation_rate_hz': expected a rate in [transfer_rate_hz, 20000] Hz"))
        << hz;
  }
}

TEST(TransferConfigTest, TheSpeedCapCheckerAcceptsUpToItsMaximaExactly) {
  EXPECT_NO_THROW(CheckLinearSpeedCap(MmToM(kMaxLinearSpeedCapMmS), "--max-speed-mm-s"));
  EXPECT_NO_THROW(CheckAngularSpeedCap(DegToRad(kMaxAngularSpeedCapDegS), "--max-angular-speed-deg-s"));
  EXPECT_NO_THROW(CheckLinearSpeedCap(MmToM(1e-6), "x"));
  try {
    CheckLinearSpeedCap(MmToM(1e300), "--max-speed-mm-s");
    ADD_FAILURE() << "1e300 mm/s accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "--max-speed-mm-s: expected a speed cap in (0, 1000] mm/s, got 1e+300 mm/s");
  }
  for (const double deg_s : {0.0, -1.0, 360.001, 1e300, std::numeric_limits<double>::quiet_NaN()}) {
    EXPECT_THROW(CheckAngularSpeedCap(DegToRad(deg_s), "a"), std::invalid_argument) << deg_s;
  }
  // transfer.yaml's caps go through the same checker.
  TransferConfig c;
  c.caps.max_linear_speed_m_s = MmToM(1000.5);
  EXPECT_EQ(ErrorOf(c), "transfer config: 'caps.max_linear_speed_mm_s': expected a speed cap in (0, 1000] mm/s, got "
                        "1000.5 mm/s");
}

}  // namespace
}  // namespace robossis::transfer
