#!/bin/bash
# Device call 67 (stop 30): Table 6.3 at equal error on mirror blocks with every hit in a pass of
# its own and the lists (this stop's final build; call 62 ran the passes over every pixel).
bash "$(dirname "$0")/equal_error.sh" mirror
