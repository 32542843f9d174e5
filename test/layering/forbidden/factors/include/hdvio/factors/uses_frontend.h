#pragma once
// fixture for test/layering: factors must not include frontend/
#include "hdvio/core/factor.h"
#include "hdvio/frontend/frame.h"
