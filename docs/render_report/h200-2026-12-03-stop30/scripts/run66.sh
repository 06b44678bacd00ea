#!/bin/bash
# Device call 66 (stop 30): Table 6.3 at equal error on glazed blocks again, with this stop's
# final build (the later passes launched over every pixel, as at stop 29; samples by weight^0.8
# among the candidates), to see the pick of call 65 hold in a second run.
bash "$(dirname "$0")/equal_error.sh" glazed
