// A forward declaration of OpenImageIO's TextureSystem, so that headers which accept a host's
// TextureSystem* do not pull in all of OpenImageIO (oiioversion.h only names the namespace).
#pragma once

#include <OpenImageIO/oiioversion.h>

OIIO_NAMESPACE_BEGIN
class TextureSystem;
OIIO_NAMESPACE_END
