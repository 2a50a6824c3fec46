/* Linked statically: tcs-run must refuse it rather than run it in real time. */
#include <stdio.h>

int main(void)
{
	puts("hello from a static binary");
	return 0;
}
