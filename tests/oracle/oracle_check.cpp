// The one instantiation of the oracle checks (oracle_check.hpp) for each point type.
#include "oracle/oracle_check.hpp"

namespace frnn::test {

FRNN_ORACLE_CHECKS(, float, 2)
FRNN_ORACLE_CHECKS(, float, 3)
FRNN_ORACLE_CHECKS(, double, 2)
FRNN_ORACLE_CHECKS(, double, 3)

}  // namespace frnn::test
