// fixture for test/layering: backend must not include learned/
#include "hdvio/factors/imu_factor.h"
#include "hdvio/learned/tcn.h"
