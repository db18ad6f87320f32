// The one translation unit that holds Boost.Asio's and Boost.Beast's
// compiled code; every other file includes their declarations only
// (tumble_asio defines BOOST_ASIO_SEPARATE_COMPILATION and
// BOOST_BEAST_SEPARATE_COMPILATION).
#include <boost/asio/impl/src.hpp>
#include <boost/beast/src.hpp>
