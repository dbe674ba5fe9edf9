// With CYCLONEDDS_URI unset, a participant uses the compiled-in loopback
// configuration (samples/cyclonedds_loopback.xml) and works. Its own
// executable: a process configures a domain once, and this one must start
// without CYCLONEDDS_URI.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "groundline/io/dds_convert.h"
#include "groundline/io/dds_pubsub.h"

namespace groundline::io {
namespace {

constexpr unsigned kDomainId = 177;

TEST(DdsDefaultConfigTest, LoopbackConfigIsTheSampleFile) {
  std::ifstream in(GROUNDLINE_DDS_LOOPBACK_XML);
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ(LoopbackConfigXml(), text.str());
  EXPECT_NE(LoopbackConfigXml().find("<NetworkInterface address=\"127.0.0.1\""), std::string::npos);
  EXPECT_NE(LoopbackConfigXml().find("<AllowMulticast>false</AllowMulticast>"), std::string::npos);
}

TEST(DdsDefaultConfigTest, UnsetUriMeansLoopbackAndItDelivers) {
  ::unsetenv("CYCLONEDDS_URI");
  DdsParticipantOptions options;
  options.domain_id = kDomainId;
  core::Result<DdsParticipant> p = DdsParticipant::Create(options);
  ASSERT_TRUE(p.ok()) << p.message();
  EXPECT_EQ(p->config_source(), "loopback");
  EXPECT_EQ(p->domain_id(), kDomainId);

  const std::string topic = "rt/p" + std::to_string(::getpid()) + "/tf";
  auto pub = DdsPublisher<RosTfMessage>::Create(*p, topic, QosPreset::kTf);
  auto sub = DdsSubscriber<RosTfMessage>::Create(*p, topic, QosPreset::kTf);
  ASSERT_TRUE(pub.ok() && sub.ok());
  ASSERT_TRUE(WaitForMatches(pub->writer(), true, 1, std::chrono::seconds(10)));
  ASSERT_TRUE(pub->Write(ToTfMessage({{1.0, "map", "odom", core::SE2(1.0, 0.0, 0.0)}}).msg()).ok());
  core::Result<DdsWaitSet> ws = DdsWaitSet::Create(*p);
  ASSERT_TRUE(ws.ok() && ws->Attach(sub->reader()).ok());
  int got = 0;
  for (int i = 0; i < 100 && got == 0; ++i) {
    ASSERT_TRUE(ws->Wait(std::chrono::milliseconds(100)).ok());
    core::Result<int> n = sub->Take([&](const RosTfMessage& m) { got += m.transforms._length; });
    ASSERT_TRUE(n.ok());
  }
  EXPECT_EQ(got, 1);
}

TEST(DdsDefaultConfigTest, BadRosDomainIdIsAnError) {
  ::setenv("ROS_DOMAIN_ID", "12x", 1);
  core::Result<std::uint32_t> id = DomainIdFromEnvironment();
  ASSERT_FALSE(id.ok());
  EXPECT_NE(id.message().find("ROS_DOMAIN_ID"), std::string::npos);
  ::setenv("ROS_DOMAIN_ID", "233", 1);
  EXPECT_FALSE(DomainIdFromEnvironment().ok());
  ::setenv("ROS_DOMAIN_ID", "232", 1);
  ASSERT_TRUE(DomainIdFromEnvironment().ok());
  EXPECT_EQ(*DomainIdFromEnvironment(), 232u);
  ::unsetenv("ROS_DOMAIN_ID");
  EXPECT_EQ(*DomainIdFromEnvironment(), 0u);
}

}  // namespace
}  // namespace groundline::io
