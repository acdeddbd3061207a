#pragma once
// incise-agent --self-test: checks what a station needs before a trainee sits down, one line per
// check ("ok   ..." or "FAIL ..."), and no force is ever commanded but zero:
//   - each device: 200 polls at 1 kHz, every state finite with a unit quaternion, no fault, and
//     it moves or not (reported, not judged: a hand may rest);
//   - the loop timer: 200 ticks at 1 kHz, the period's p99 jitter (fails above 1 ms);
//   - the link: connect, hello, welcome (the token is valid), then 20 WebSocket pings timed
//     (round-trip median and maximum; fails above 50 ms median).

#include <boost/asio/ssl/context.hpp>
#include <iosfwd>
#include <vector>

#include "devices/agent/options.h"
#include "devices/device.h"

namespace incise::devices::agent {

// Returns true if every check passed; writes the lines to out. `tls`: for a wss:// server, the
// context that verifies it (null for ws://).
bool run_self_test(const AgentOptions& options, const std::vector<Device*>& devices,
                   boost::asio::ssl::context* tls, std::ostream& out);

}  // namespace incise::devices::agent
