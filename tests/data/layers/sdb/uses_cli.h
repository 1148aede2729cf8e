// A header that breaks the layer rules on purpose (sdb/ may not include cli/).
#pragma once
#include "cli/command.h"
