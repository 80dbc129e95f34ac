// Interface of the HRPP kernels: binding slots, workgroup sizes and push constants of
// shaders/hrpp_*.comp. Included by the host (host/gpu/) and by GLSL; one definition.
#ifndef HRPP_HRPP_INTERFACE_H
#define HRPP_HRPP_INTERFACE_H

#include "hrpp_types.h"

// hrpp_hash_rays.comp: keys[i] = hash(rays[i]) under params.
#define HRPP_HASH_WORKGROUP_SIZE 64
#define HRPP_HASH_BINDING_RAYS 0
#define HRPP_HASH_BINDING_KEYS 1
#define HRPP_HASH_BINDING_PARAMS 2
#define HRPP_HASH_BINDING_COUNT 3

#endif  // HRPP_HRPP_INTERFACE_H
