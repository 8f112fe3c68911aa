// Control requests: sequences, resolution by acks (applied, ignored, rejected), retransmission
// with the same sequence, time-outs, multi-datagram requests and the bounded table.
#include "service/control_requests.h"

#include <gtest/gtest.h>

#include "wire/packet.h"

namespace mocap::service {
namespace {

constexpr uint64_t kMs = 1'000'000;

v1::Control Threshold(uint32_t value) {
  v1::Control c;
  c.mutable_set_threshold()->set_value(value);
  return c;
}

v1::ControlAck Ack(const v1::Packet& sent, v1::ControlResult result, const std::string& reason = {}) {
  v1::ControlAck a;
  a.set_node_id(sent.control().node_id());
  a.set_sequence(sent.control().sequence());
  a.set_result(result);
  a.set_reason(reason);
  return a;
}

TEST(ControlRequests, SequencesIncreaseAndPacketsAreValid) {
  ControlRequestsOptions options;
  options.first_sequence = 4000;
  ControlRequests requests(options);
  const SubmitResult a = requests.Submit(3, {Threshold(50)}, 0);
  const SubmitResult b = requests.Submit(4, {Threshold(60), Threshold(70)}, 0);
  ASSERT_TRUE(a.ok && b.ok);
  EXPECT_NE(a.request_id, b.request_id);
  ASSERT_EQ(a.send.size(), 1u);
  ASSERT_EQ(b.send.size(), 2u);
  EXPECT_EQ(a.send[0].control().node_id(), 3u);
  EXPECT_EQ(a.send[0].control().sequence(), 4000u);
  EXPECT_EQ(b.send[0].control().node_id(), 4u);
  EXPECT_EQ(b.send[0].control().sequence(), 4001u);
  EXPECT_EQ(b.send[1].control().sequence(), 4002u);
  for (const auto& p : b.send) EXPECT_EQ(wire::Validate(p), "");
  EXPECT_EQ(requests.pending(), 2u);
}

TEST(ControlRequests, AppliedAndRejectedByTheNodesAnswer) {
  ControlRequests requests;
  const SubmitResult a = requests.Submit(3, {Threshold(50)}, 10 * kMs);
  const SubmitResult b = requests.Submit(3, {Threshold(51)}, 10 * kMs);
  auto done = requests.OnAck(Ack(a.send[0], v1::CONTROL_RESULT_APPLIED), 12 * kMs);
  ASSERT_TRUE(done.has_value());
  EXPECT_EQ(done->request_id, a.request_id);
  EXPECT_EQ(done->outcome, RequestOutcome::kApplied);
  EXPECT_EQ(done->finished_ns - done->submitted_ns, 2 * kMs);
  done = requests.OnAck(Ack(b.send[0], v1::CONTROL_RESULT_REJECTED, "control: threshold outside 1..255"),
                        13 * kMs);
  ASSERT_TRUE(done.has_value());
  EXPECT_EQ(done->outcome, RequestOutcome::kRejected);
  EXPECT_EQ(done->reason, "control: threshold outside 1..255");
  EXPECT_STREQ(RequestOutcomeName(done->outcome), "rejected");
  EXPECT_EQ(requests.pending(), 0u);
  // The same answer again (a retransmission crossed it) finishes nothing.
  EXPECT_FALSE(requests.OnAck(Ack(a.send[0], v1::CONTROL_RESULT_APPLIED), 14 * kMs).has_value());
  EXPECT_EQ(requests.stray_acks(), 1u);
}

TEST(ControlRequests, AnAckFromAnotherNodeDoesNotResolve) {
  ControlRequests requests;
  const SubmitResult a = requests.Submit(3, {Threshold(50)}, 0);
  v1::ControlAck wrong = Ack(a.send[0], v1::CONTROL_RESULT_APPLIED);
  wrong.set_node_id(4);
  EXPECT_FALSE(requests.OnAck(wrong, kMs).has_value());
  EXPECT_EQ(requests.pending(), 1u);
  EXPECT_EQ(requests.stray_acks(), 1u);
}

TEST(ControlRequests, UnansweredIsResentThenTimesOut) {
  ControlRequestsOptions options;
  options.timeout_ns = 1000 * kMs;
  options.retransmit_after_ns = 300 * kMs;
  ControlRequests requests(options);
  const SubmitResult a = requests.Submit(7, {Threshold(50)}, 0);
  EXPECT_EQ(requests.NextDeadline(), 300 * kMs);
  auto tick = requests.Tick(299 * kMs);
  EXPECT_TRUE(tick.resend.empty());
  tick = requests.Tick(300 * kMs);
  ASSERT_EQ(tick.resend.size(), 1u);
  EXPECT_EQ(tick.resend[0].control().sequence(), a.send[0].control().sequence());
  EXPECT_EQ(requests.NextDeadline(), 600 * kMs);
  EXPECT_EQ(requests.Tick(600 * kMs).resend.size(), 1u);
  EXPECT_EQ(requests.Tick(900 * kMs).resend.size(), 1u);
  EXPECT_EQ(requests.NextDeadline(), 1000 * kMs);
  tick = requests.Tick(1000 * kMs);
  EXPECT_TRUE(tick.resend.empty());
  ASSERT_EQ(tick.finished.size(), 1u);
  EXPECT_EQ(tick.finished[0].outcome, RequestOutcome::kTimedOut);
  EXPECT_EQ(tick.finished[0].retransmissions, 3u);
  EXPECT_NE(tick.finished[0].reason.find("node 7"), std::string::npos);
  EXPECT_EQ(requests.pending(), 0u);
  EXPECT_FALSE(requests.NextDeadline().has_value());
  // The node's answer after the deadline is a stray.
  EXPECT_FALSE(requests.OnAck(Ack(a.send[0], v1::CONTROL_RESULT_APPLIED), 1001 * kMs).has_value());
}

TEST(ControlRequests, NoRetransmissionWhenDisabled) {
  ControlRequestsOptions options;
  options.retransmit_after_ns = 0;
  ControlRequests requests(options);
  requests.Submit(7, {Threshold(50)}, 0);
  EXPECT_EQ(requests.NextDeadline(), options.timeout_ns);
  EXPECT_TRUE(requests.Tick(options.timeout_ns - 1).resend.empty());
}

TEST(ControlRequests, MultiDatagramRequests) {
  ControlRequests requests;
  // Applied once every part is applied or ignored, and only the unanswered part is resent.
  SubmitResult a = requests.Submit(2, {Threshold(1), Threshold(2), Threshold(3)}, 0);
  EXPECT_FALSE(requests.OnAck(Ack(a.send[0], v1::CONTROL_RESULT_APPLIED), kMs).has_value());
  EXPECT_FALSE(requests.OnAck(Ack(a.send[2], v1::CONTROL_RESULT_IGNORED, "already"), kMs).has_value());
  const auto tick = requests.Tick(ControlRequestsOptions{}.retransmit_after_ns);
  ASSERT_EQ(tick.resend.size(), 1u);
  EXPECT_EQ(tick.resend[0].control().sequence(), a.send[1].control().sequence());
  auto done = requests.OnAck(Ack(a.send[1], v1::CONTROL_RESULT_APPLIED), 2 * kMs);
  ASSERT_TRUE(done.has_value());
  EXPECT_EQ(done->outcome, RequestOutcome::kApplied);
  EXPECT_EQ(done->answered, 3u);

  // Every part ignored: nothing changed.
  a = requests.Submit(2, {Threshold(1), Threshold(2)}, 0);
  requests.OnAck(Ack(a.send[1], v1::CONTROL_RESULT_IGNORED, "control: mask chunk already stored"), kMs);
  done = requests.OnAck(Ack(a.send[0], v1::CONTROL_RESULT_IGNORED, "control: mask chunk already stored"), kMs);
  ASSERT_TRUE(done.has_value());
  EXPECT_EQ(done->outcome, RequestOutcome::kIgnored);
  EXPECT_EQ(done->reason, "control: mask chunk already stored");

  // One part rejected: the request is rejected at once, later answers are strays.
  a = requests.Submit(2, {Threshold(1), Threshold(2)}, 0);
  done = requests.OnAck(Ack(a.send[1], v1::CONTROL_RESULT_REJECTED, "control: mask image in too many chunks"), kMs);
  ASSERT_TRUE(done.has_value());
  EXPECT_EQ(done->outcome, RequestOutcome::kRejected);
  EXPECT_EQ(done->answered, 1u);
  const uint64_t strays = requests.stray_acks();
  EXPECT_FALSE(requests.OnAck(Ack(a.send[0], v1::CONTROL_RESULT_APPLIED), kMs).has_value());
  EXPECT_EQ(requests.stray_acks(), strays + 1);
  EXPECT_EQ(requests.pending(), 0u);
}

TEST(ControlRequests, PendingTableIsBounded) {
  ControlRequestsOptions options;
  options.max_pending = 2;
  ControlRequests requests(options);
  EXPECT_TRUE(requests.Submit(1, {Threshold(1)}, 0).ok);
  const SubmitResult second = requests.Submit(2, {Threshold(1)}, 0);
  EXPECT_TRUE(second.ok);
  const SubmitResult third = requests.Submit(3, {Threshold(1)}, 0);
  EXPECT_FALSE(third.ok);
  EXPECT_NE(third.error, "");
  EXPECT_TRUE(third.send.empty());
  requests.OnAck(Ack(second.send[0], v1::CONTROL_RESULT_APPLIED), 1);
  EXPECT_TRUE(requests.Submit(3, {Threshold(1)}, 2).ok);
}

TEST(ControlRequests, ProgrammingErrorsThrow) {
  ControlRequests requests;
  EXPECT_THROW(requests.Submit(0, {Threshold(1)}, 0), std::invalid_argument);
  EXPECT_THROW(requests.Submit(1, {}, 0), std::invalid_argument);
  v1::Control preview;
  preview.mutable_preview_request()->set_downscale(3);
  EXPECT_THROW(requests.Submit(1, {preview}, 0), std::invalid_argument);
  EXPECT_THROW(requests.Submit(1, std::vector<v1::Control>(65, Threshold(1)), 0), std::invalid_argument);
  EXPECT_EQ(requests.pending(), 0u);
  ControlRequestsOptions options;
  options.retransmit_after_ns = options.timeout_ns;
  EXPECT_THROW(ControlRequests{options}, std::invalid_argument);
}

}  // namespace
}  // namespace mocap::service
