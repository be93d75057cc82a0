/* builtin_mirror.c - cornell-mirror: the Cornell box with the tall block a mirror and a glass
 * sphere on the floor. PLACEHOLDER: the images issue turns the tall block into a mirror and adds
 * the sphere; until then the scene is the plain Cornell box. */
#include "scene/scene.h"

rad_status rad_builtin_cornell_mirror(rad_scene *scene) {
    (void)scene;
    return RAD_OK;
}
