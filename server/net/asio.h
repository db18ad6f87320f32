// Boost.Asio for the net layer. Boost 1.74's Asio uses std::exchange
// without including <utility>, which GCC 12 in C++20 mode does not pull in
// by itself; include it first. (Targets linking tumble_asio also get it
// forced on the command line.)
#pragma once

#include <utility>

#include <boost/asio.hpp>
