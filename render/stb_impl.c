/* The one translation unit that compiles stb_image_write (third-party, built without vx warnings). */
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>
