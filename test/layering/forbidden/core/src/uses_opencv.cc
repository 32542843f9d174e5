// fixture for test/layering: core must not include OpenCV (only core/io may)
#include <opencv2/core.hpp>
