#pragma once
// The off-line chain lives in the runtime library (src/teleop/offline_chain.h); the command line and the demo reach
// it through these names, with the chain configured from the app's data folder.

#include "src/apps/app_context.h"
#include "src/core/files.h"
#include "src/teleop/offline_chain.h"

namespace robossis::apps {

using teleop::ChainSetup;
using teleop::HcRecordsCsv;
using teleop::JointsCsv;
using teleop::PulsesCsv;
using teleop::RunMoveChain;
using teleop::RunTransferChain;
using teleop::SetPointsCsv;
using teleop::SlowTraceCsv;
using teleop::SummaryJson;
using teleop::TransferSummary;
using teleop::TransferTrace;

// The chain as configured in the app's data folder (transfer.yaml, actuation.yaml, follower.yaml).
inline ChainSetup DefaultChainSetup(const AppContext& app, const robot::RsrModel& model) {
  return teleop::LoadChainSetup(app.data_dir / "config", model);
}

}  // namespace robossis::apps
